//! Two chart kinds the studies share, as figures: a grid of stacked histograms (the
//! samples that kept contact and those that jumped) and a chart of probabilities with
//! their 95 % intervals.

use camsim_scene_file::units::Unit;

use crate::figure::palette::{BLUE, GREY, RED};
use crate::figure::{
    Axis, Band, Bar, Colour, Entry, Figure, HAlign, Mark, Note, Panel, Series, Shape, Strip, Style,
    Swatch, Ticks, VAlign,
};

/// Colour of the samples that kept contact.
pub const HELD: Colour = BLUE;
/// Colour of the samples that jumped.
pub const JUMPED: Colour = RED;
/// Colour of a histogram of every sample, not split by jump (the profiles).
pub const ALL: Colour = GREY;

/// One panel of a grid of histograms: the samples that kept contact and those that
/// jumped, counted over the same equal bins of `lo..hi`, stacked.
pub struct HistPanel {
    /// The panel's caption.
    pub caption: String,
    /// The quantity on the x axis, without its unit.
    pub quantity: String,
    /// Its unit (`None`: dimensionless); `lo` and `hi` are in its inch member.
    pub unit: Option<Unit>,
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
    pub colour: Colour,
}

/// A grid of stacked histograms (held below, jumped on top), `cols` panels a row,
/// titled `title` with a legend of `legend` (colour, text) under it; the count axis
/// titled `count` ("cams").
pub fn histograms(
    title: &str,
    legend: &[(Colour, String)],
    count: &str,
    panels: &[HistPanel],
    cols: usize,
) -> Figure {
    let cols = cols.max(1);
    let rows = panels.len().div_ceil(cols).max(1);
    let size = (400 * cols as u32, 90 + 320 * rows as u32);
    let mut fig = Figure::new(
        title,
        size,
        panels.iter().map(|p| histogram(p, count)).collect(),
    );
    fig.columns = cols;
    fig.strip = Strip {
        entries: legend
            .iter()
            .map(|(c, t)| Entry {
                swatch: Swatch::Fill(*c, 1.0),
                text: t.clone(),
            })
            .collect(),
        columns: 0,
        note: None,
    };
    fig
}

/// One stacked histogram.
fn histogram(h: &HistPanel, count: &str) -> Panel {
    let top = h
        .held
        .iter()
        .zip(&h.jumped)
        .map(|(a, b)| a + b)
        .max()
        .unwrap_or(1)
        .max(1);
    let ymax = f64::from(top + top / 8 + 1);
    let mut x = match h.unit {
        Some(u) => Axis::of(&h.quantity, u),
        None => Axis::plain(&h.quantity, ""),
    }
    .range(h.lo, h.hi)
    .ticks(Ticks::Auto(5));
    x.thousands = true;
    let step = crate::figure::render::nice_step(ymax / 6.0).max(1.0);
    let major = (0..)
        .map(|k| f64::from(k) * step)
        .take_while(|v| *v <= ymax)
        .collect();
    let y = Axis::plain(count, "").range(0.0, ymax).ticks(Ticks::At {
        major,
        minor: Vec::new(),
    });
    let mut p = Panel::new(x, y);
    p.caption = Some(h.caption.clone());
    let w = (h.hi - h.lo) / h.held.len().max(1) as f64;
    for (k, (&held, &jumped)) in h.held.iter().zip(&h.jumped).enumerate() {
        let x = (h.lo + k as f64 * w, h.lo + (k + 1) as f64 * w);
        let (held, jumped) = (f64::from(held), f64::from(jumped));
        if held > 0.0 {
            p.bars.push(Bar {
                x,
                y: (0.0, held),
                colour: h.colour,
                edge: None,
            });
        }
        if jumped > 0.0 {
            p.bars.push(Bar {
                x,
                y: (held, held + jumped),
                colour: JUMPED,
                edge: None,
            });
        }
    }
    p.remark = h.note.clone();
    p
}

/// One bar of a probability chart: its name, the count of n and its interval.
pub struct ProbBar {
    /// The bar's name (a period, "whole revolution").
    pub name: String,
    /// The probability with its 95 % interval.
    pub p: crate::stats::Probability,
}

/// A chart of probabilities with their 95 % intervals (a dot and a bar from lo95 to
/// hi95 each, its count of `n` and interval written beside it).
pub fn probabilities(title: &str, y_title: &str, n: u64, bars: &[ProbBar]) -> Figure {
    let top = bars
        .iter()
        .map(|b| b.p.hi95)
        .fold(0.0f64, f64::max)
        .mul_add(1.25, 0.0)
        .clamp(0.01, 1.0);
    let names = bars.iter().map(|b| b.name.clone()).collect();
    let x_title = format!("each over {n} cams; the bar is the 95 % Wilson interval");
    let k = bars.len() as f64;
    let x = Axis::plain(&x_title, "")
        .range(-0.5, k - 0.5)
        .ticks(Ticks::Named(names));
    let mut p = Panel::new(x, Axis::plain(y_title, "").range(0.0, top));
    let at = |i: usize| i as f64;
    let whiskers = bars
        .iter()
        .enumerate()
        .map(|(i, b)| (at(i), b.p.lo95, b.p.hi95))
        .collect();
    p.bands.push(Band {
        label: None,
        colour: JUMPED,
        alpha: 3.0,
        shape: Shape::Whiskers(whiskers),
    });
    let dots = bars
        .iter()
        .enumerate()
        .map(|(i, b)| (at(i), b.p.p))
        .collect();
    p.series.push(Series {
        label: None,
        points: dots,
        style: Style::Points(Mark::Dot, JUMPED),
    });
    for (i, b) in bars.iter().enumerate() {
        // Centred above the interval, or below it when it reaches the top.
        let above = b.p.hi95 < 0.85 * top;
        let y = if above {
            b.p.hi95 + 0.02 * top
        } else {
            b.p.lo95 - 0.02 * top
        };
        let text = format!("{} of {n}: {}", b.p.count, b.p.text(3));
        let v = if above { VAlign::Above } else { VAlign::Below };
        p.notes.push(Note::new((at(i), y), text, HAlign::Centre, v));
    }
    Figure::new(title, (260 * bars.len().max(2) as u32 + 160, 620), vec![p])
}
