//! The one renderer: draws a [`Figure`] into a PNG with the one style (the constants
//! below). The only module that calls plotters' chart builder.

use std::ops::Range;

use anyhow::{anyhow, Result};
use plotters::coord::ranged1d::{KeyPointHint, NoDefaultFormatting, Ranged, ValueFormatter};
use plotters::coord::types::RangedCoordf64;
use plotters::coord::Shift;
use plotters::element::DashedPathElement;
use plotters::prelude::*;
use plotters::style::text_anchor::{HPos, Pos, VPos};

use super::{
    At, Axis, Band, Dash, Entry, Figure, FigureError, HAlign, Legend, Mark, Panel, Scale, Series,
    Shape, Stroke, Style, Swatch, Ticks, VAlign,
};
use crate::output::AtomicDir;
use crate::units::Units;

/// DejaVu Sans (Bitstream Vera licence, see `host-sim/assets/DejaVuSans-LICENSE.txt`).
static FONT_TTF: &[u8] = include_bytes!("../../assets/DejaVuSans.ttf");
/// The family name the embedded font is registered under.
const FONT: &str = "sans-serif";

/// Registers the embedded font with plotters once per process (the growth example
/// draws with it too).
pub fn ensure_font() -> Result<()> {
    static OK: std::sync::OnceLock<bool> = std::sync::OnceLock::new();
    let ok = *OK
        .get_or_init(|| plotters::style::register_font(FONT, FontStyle::Normal, FONT_TTF).is_ok());
    anyhow::ensure!(ok, "the embedded DejaVu Sans font could not be parsed");
    Ok(())
}

/// A colour (red, green, blue).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Colour(pub u8, pub u8, pub u8);

impl Colour {
    fn rgb(self) -> RGBColor {
        RGBColor(self.0, self.1, self.2)
    }
}

/// The palette (Tableau's ten, black and a light orange), named by colour.
pub mod palette {
    use super::Colour;
    /// Blue: a simulated or theoretical quantity, the first series.
    pub const BLUE: Colour = Colour(31, 119, 180);
    /// Orange.
    pub const ORANGE: Colour = Colour(255, 127, 14);
    /// Green.
    pub const GREEN: Colour = Colour(44, 160, 44);
    /// Red: a jump, the best rank.
    pub const RED: Colour = Colour(214, 39, 40);
    /// Purple.
    pub const PURPLE: Colour = Colour(148, 103, 189);
    /// Brown.
    pub const BROWN: Colour = Colour(140, 86, 75);
    /// Pink.
    pub const PINK: Colour = Colour(227, 119, 194);
    /// Grey.
    pub const GREY: Colour = Colour(127, 127, 127);
    /// Olive.
    pub const OLIVE: Colour = Colour(188, 189, 34);
    /// Cyan.
    pub const CYAN: Colour = Colour(23, 190, 207);
    /// Black.
    pub const BLACK: Colour = Colour(0, 0, 0);
    /// White (text on a dark fill).
    pub const WHITE: Colour = Colour(255, 255, 255);
    /// Light orange.
    pub const LIGHT_ORANGE: Colour = Colour(255, 187, 120);
    /// Light red: a jump's shading.
    pub const LIGHT_RED: Colour = Colour(255, 150, 150);
    /// Dark grey: a reference line (the operating speed, a revolution's start).
    pub const DARK_GREY: Colour = Colour(90, 90, 90);
    /// Mid grey: a theoretical curve under a coloured one.
    pub const MID_GREY: Colour = Colour(150, 150, 150);
    /// Light grey: a faint reference line (a period's start).
    pub const LIGHT_GREY: Colour = Colour(170, 170, 170);
    /// The twelve colours in order, for series that are told apart by colour alone.
    pub const SERIES: [Colour; 12] = [
        BLUE,
        ORANGE,
        GREEN,
        RED,
        PURPLE,
        BROWN,
        PINK,
        GREY,
        OLIVE,
        CYAN,
        BLACK,
        LIGHT_ORANGE,
    ];
}

/// The title's font size and the height of its strip, pixels.
const TITLE_FONT: u32 = 24;
const TITLE_H: u32 = 48;
/// Font sizes: tick labels, axis titles, panel captions, legends, notes.
const TICK_FONT: u32 = 15;
const AXIS_FONT: u32 = 17;
const CAPTION_FONT: u32 = 17;
const LEGEND_FONT: u32 = 16;
const NOTE_FONT: u32 = 14;
/// The font size of a large note (a heat map's cell value).
const LARGE_NOTE_FONT: u32 = 20;
/// The font size of a row's title (a row of panels about one thing).
const ROW_TITLE_FONT: u32 = 19;
/// Margins around a panel, pixels.
const MARGIN: u32 = 8;
const MARGIN_RIGHT: u32 = 24;
/// Grid lines: at the labelled ticks, and the light ones between.
const GRID: RGBColor = RGBColor(215, 215, 215);
const GRID_LIGHT: RGBColor = RGBColor(240, 240, 240);
/// The border of a legend box.
const LEGEND_BORDER: RGBColor = RGBColor(160, 160, 160);
/// Grey text (a strip's note).
const NOTE_GREY: RGBColor = RGBColor(90, 90, 90);
/// A legend strip: its left edge, its row height, a swatch's width.
const STRIP_LEFT: i32 = 110;
const STRIP_ROW: i32 = 26;
const SWATCH_W: i32 = 30;
/// A legend box's row height inside a panel, pixels.
const BOX_ROW: f64 = 20.0;
/// The narrowest y label area of panels over one another, pixels: a panel keeps its
/// plotting area when the tick labels of the one below it widen a little.
const Y_LABEL_MIN: u32 = 100;
/// The data's margin on an axis with no range given: 5 % of its span either side.
const PAD: f64 = 0.05;
/// The narrowest a span (a jump) is drawn, pixels.
const MIN_SPAN_PX: f64 = 3.0;
/// A dash pattern: pixels on, pixels off.
type Pattern = (u32, u32);

/// Each dash's pattern on a line and on a legend swatch; none: solid.
fn dash_pattern(d: Dash, swatch: bool) -> Option<Pattern> {
    const PATTERNS: [(Dash, Pattern, Pattern); 2] = [
        (Dash::Dashed, (10, 6), (7, 5)),
        (Dash::Dotted, (2, 5), (2, 4)),
    ];
    PATTERNS
        .iter()
        .find(|p| p.0 == d)
        .map(|&(_, line, sw)| if swatch { sw } else { line })
}
/// Light grid lines between two labelled ticks of a linear axis.
const MINOR_PER_MAJOR: f64 = 5.0;

/// Draws `fig` with its axes in `units` as the PNG `file` in `dir` (to the file's
/// temporary: the caller commits `dir`).
pub fn draw(dir: &mut AtomicDir, file: &str, fig: &Figure, units: Units) -> Result<()> {
    let (buf, _) = render(&fig.clone().in_units(units))
        .map_err(|e| anyhow!("cannot draw plot {file}: {e}"))?;
    crate::plot::save_png(dir, file, &buf, fig.size)
}

/// An axis's range, from and to.
pub type Span = (f64, f64);

/// Pixel ranges (x, y) of a panel's plotting area.
pub type PixelArea = (Range<i32>, Range<i32>);

/// Draws a figure (already in its units) into an RGB buffer; returns it and each
/// panel's plotting area. Every panel's ranges are checked before anything is drawn.
pub fn render(fig: &Figure) -> Result<(Vec<u8>, Vec<PixelArea>)> {
    ensure_font()?;
    for p in &fig.panels {
        ranges(p, 0.0)?;
    }
    let size = fig.size;
    let mut buf = vec![0u8; size.0 as usize * size.1 as usize * 3];
    let areas = {
        let root = BitMapBackend::with_buffer(&mut buf, size).into_drawing_area();
        let areas = draw_figure(&root, fig).map_err(|e| anyhow!("{e}"))?;
        root.present().map_err(|e| anyhow!("{e}"))?;
        areas
    };
    Ok((buf, areas))
}

/// The (x, y) ranges a panel is drawn over: each axis's own, or its data's (series,
/// bands, bars and marker lines) with a margin; the y range raised by `legend_frac` of its height for
/// a legend box. A panel with no finite value on an axis is refused.
pub fn ranges(p: &Panel, legend_frac: f64) -> Result<(Span, Span), FigureError> {
    let x = axis_range(&p.x, values(p, true).into_iter(), 0.0, &p.name())?;
    let y = axis_range(&p.y, values(p, false).into_iter(), legend_frac, &p.name())?;
    Ok((x, y))
}

/// Every value of `p` on its x axis (`x`) or its y axis: its series', bands', bars' and
/// marker lines'.
fn values(p: &Panel, x: bool) -> Vec<f64> {
    let pick = |q: (f64, f64)| if x { q.0 } else { q.1 };
    let series = p
        .series
        .iter()
        .flat_map(|s| s.points.iter().map(|q| pick(*q)));
    let bars = p.bars.iter().flat_map(|b| {
        let (lo, hi) = if x { b.x } else { b.y };
        [lo, hi]
    });
    let markers = p.markers.iter().filter_map(|m| match (m.at, x) {
        (At::X(v), true) | (At::Y(v), false) => Some(v),
        _ => None,
    });
    series
        .chain(p.bands.iter().flat_map(|b| band_values(b, x)))
        .chain(bars)
        .chain(markers)
        .collect()
}

/// A band's x (`x`) or y values.
fn band_values(b: &Band, x: bool) -> Vec<f64> {
    match &b.shape {
        Shape::Span(a, c) if x => vec![*a, *c],
        Shape::Span(..) => Vec::new(),
        Shape::Between(v) | Shape::Whiskers(v) if x => v.iter().map(|q| q.0).collect(),
        Shape::Between(v) | Shape::Whiskers(v) => v.iter().flat_map(|q| [q.1, q.2]).collect(),
    }
}

/// An axis's range: its own, checked, or around `values` (their finite, and on a log
/// axis positive, members) with [`PAD`] and, above, room for a legend of `legend_frac`.
fn axis_range(
    a: &Axis,
    values: impl Iterator<Item = f64>,
    legend_frac: f64,
    panel: &str,
) -> Result<(f64, f64), FigureError> {
    let log = a.scale == Scale::Log;
    if let Some((lo, hi)) = a.range {
        let ok = lo.is_finite() && hi.is_finite() && hi > lo && (!log || lo > 0.0);
        return if ok {
            Ok((lo, hi))
        } else {
            Err(FigureError::BadRange {
                axis: a.label(),
                range: (lo, hi),
            })
        };
    }
    let seen = values.filter(|v| v.is_finite() && (!log || *v > 0.0)).fold(
        None,
        |acc: Option<(f64, f64)>, v| match acc {
            None => Some((v, v)),
            Some((l, h)) => Some((l.min(v), h.max(v))),
        },
    );
    let (mut lo, mut hi) = seen.ok_or_else(|| FigureError::NoFiniteData {
        panel: panel.to_string(),
    })?;
    if log {
        let lo = 10f64.powf(lo.log10().floor());
        return Ok((lo, 10f64.powf(hi.log10().ceil()).max(10.0 * lo)));
    }
    if a.zero {
        (lo, hi) = (lo.min(0.0), hi.max(0.0));
    }
    let scale = lo.abs().max(hi.abs());
    if hi - lo <= 1e-12 * scale.max(1e-300) {
        // Flat data: a window of ±1 % of the value (±1 around zero).
        let half = if scale > 0.0 { 0.01 * scale } else { 1.0 };
        (lo, hi) = (lo - half, hi + half);
    }
    let span = hi - lo;
    // Data occupy (1 - f) of the height with a legend box of f on top.
    let f = legend_frac.clamp(0.0, 0.6);
    let top = (1.05 * f / (1.0 - f)).max(PAD);
    let below = if a.zero && lo == 0.0 { 0.0 } else { PAD };
    Ok((lo - below * span, hi + top * span))
}

/// An axis's coordinate: linear or log over a range, with its own key points (labelled
/// ticks) and light points (grid lines between).
struct Coord {
    lo: f64,
    hi: f64,
    log: bool,
    major: Vec<f64>,
    minor: Vec<f64>,
}

impl Coord {
    fn new(a: &Axis, (lo, hi): (f64, f64)) -> Self {
        let log = a.scale == Scale::Log;
        let (major, minor) = match &a.ticks {
            Ticks::At { major, minor } => (major.clone(), minor.clone()),
            Ticks::Named(names) => ((0..names.len()).map(|k| k as f64).collect(), Vec::new()),
            Ticks::Auto(n) if log => {
                let decades = (hi / lo).log10();
                let m: &[f64] = if decades * 3.0 <= *n as f64 {
                    &[1.0, 2.0, 5.0]
                } else {
                    &[1.0]
                };
                let all = [1.0, 2.0, 3.0, 4.0, 5.0, 6.0, 7.0, 8.0, 9.0];
                (
                    crate::plot::log_key_points(lo, hi, m),
                    crate::plot::log_key_points(lo, hi, &all),
                )
            }
            Ticks::Auto(n) => {
                let step = nice_step((hi - lo) / (*n).max(1) as f64);
                (
                    multiples(lo, hi, step),
                    multiples(lo, hi, step / MINOR_PER_MAJOR),
                )
            }
        };
        let keep = |v: &Vec<f64>| {
            v.iter()
                .copied()
                .filter(|t| *t >= lo - 1e-9 * (hi - lo) && *t <= hi + 1e-9 * (hi - lo))
                .collect()
        };
        Self {
            major: keep(&major),
            minor: keep(&minor),
            lo,
            hi,
            log,
        }
    }
}

/// The smallest 1, 2 or 5 times a power of ten at least `rough`.
pub fn nice_step(rough: f64) -> f64 {
    if !(rough.is_finite() && rough > 0.0) {
        return 1.0;
    }
    let p = 10f64.powf(rough.log10().floor());
    [1.0, 2.0, 5.0, 10.0]
        .into_iter()
        .map(|m| m * p)
        .find(|s| *s >= rough * (1.0 - 1e-9))
        .unwrap_or(10.0 * p)
}

/// The multiples of `step` in `lo..=hi`.
fn multiples(lo: f64, hi: f64, step: f64) -> Vec<f64> {
    let first = (lo / step).ceil() as i64;
    let last = (hi / step).floor() as i64;
    if last - first > 10_000 {
        return Vec::new();
    }
    (first..=last).map(|k| k as f64 * step).collect()
}

impl Ranged for Coord {
    type FormatOption = NoDefaultFormatting;
    type ValueType = f64;
    fn map(&self, value: &f64, limit: (i32, i32)) -> i32 {
        if self.log {
            let v = if *value > 0.0 {
                value.log10()
            } else {
                self.lo.log10() - 1.0
            };
            let c: RangedCoordf64 = (self.lo.log10()..self.hi.log10()).into();
            c.map(&v, limit)
        } else {
            let c: RangedCoordf64 = (self.lo..self.hi).into();
            c.map(value, limit)
        }
    }
    fn key_points<Hint: KeyPointHint>(&self, hint: Hint) -> Vec<f64> {
        if hint.weight().allow_light_points() {
            self.minor.clone()
        } else {
            self.major.clone()
        }
    }
    fn range(&self) -> Range<f64> {
        self.lo..self.hi
    }
}

impl ValueFormatter<f64> for Coord {
    fn format(value: &f64) -> String {
        format!("{value}")
    }
}

/// A tick's label on axis `a` spanning `lo..hi`.
pub(super) fn tick_label(a: &Axis, v: f64, span: (f64, f64)) -> String {
    let t = unsigned_tick_label(a, v, span);
    if a.signed && v > 0.0 && !t.is_empty() && t != "0" {
        format!("+{t}")
    } else {
        t
    }
}

/// A tick's label without a sign on positive values.
fn unsigned_tick_label(a: &Axis, v: f64, (lo, hi): (f64, f64)) -> String {
    if !a.labelled {
        return String::new();
    }
    match (&a.ticks, a.scale) {
        (Ticks::Named(names), _) => {
            let i = v.round();
            let hit = (v - i).abs() < 1e-6 && i >= 0.0;
            hit.then(|| names.get(i as usize).cloned())
                .flatten()
                .unwrap_or_default()
        }
        (_, Scale::Log) => log_tick(v),
        (Ticks::At { major, .. }, _) if major.len() > 1 => {
            // Decimals for the ticks' own step (fmt_tick assumes about 8 ticks a span).
            let step = major
                .windows(2)
                .map(|w| (w[1] - w[0]).abs())
                .fold(f64::INFINITY, f64::min);
            let v = if v.abs() < 1e-9 * step { 0.0 } else { v };
            crate::plot::fmt_tick(v, 8.0 * step)
        }
        _ => {
            let span = hi - lo;
            let v = if v.abs() < 1e-9 * span { 0.0 } else { v };
            crate::plot::fmt_tick(v, span)
        }
    }
}

/// A log axis's tick in plain digits from 0.001 to 10 000 000 ("200 000", "0.05"), in
/// powers of ten outside ("1e-9").
pub fn log_tick(v: f64) -> String {
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

type Area<DB> = DrawingArea<DB, Shift>;
type DrawResult<T, DB> =
    std::result::Result<T, DrawingAreaErrorKind<<DB as DrawingBackend>::ErrorType>>;
type Chart<'a, DB> = ChartContext<'a, DB, Cartesian2d<Coord, Coord>>;

/// The figure: its title, its legend strip, its panels in their grid.
fn draw_figure<DB: DrawingBackend>(
    root: &Area<DB>,
    fig: &Figure,
) -> DrawResult<Vec<PixelArea>, DB> {
    root.fill(&WHITE)?;
    let (head, rest) = root.split_vertically(TITLE_H);
    let (w, _) = head.dim_in_pixel();
    head.draw(&Text::new(
        fig.title.as_str(),
        (w as i32 / 2, 12),
        (FONT, TITLE_FONT)
            .into_font()
            .color(&BLACK)
            .pos(Pos::new(HPos::Center, VPos::Top)),
    ))?;
    let (strip, body) = rest.split_vertically(strip_height(fig));
    draw_strip(&strip, fig)?;
    let cells = grid(&body, fig)?;
    // One y label width for every panel, so panels over one another line up.
    let y_area = fig
        .panels
        .iter()
        .zip(&cells)
        .map(|(p, a)| y_label_area(a, p))
        .max()
        .unwrap_or(0)
        .max(if fig.columns <= 1 { Y_LABEL_MIN } else { 0 });
    let mut areas = Vec::new();
    for (p, area) in fig.panels.iter().zip(&cells) {
        areas.push(draw_panel(area, p, y_area)?);
    }
    Ok(areas)
}

/// The legend strip's height, pixels.
fn strip_height(fig: &Figure) -> u32 {
    let s = &fig.strip;
    if s.entries.is_empty() && s.note.is_none() {
        return 0;
    }
    let rows = match s.columns {
        0 => 1,
        c => s.entries.len().div_ceil(c),
    };
    (STRIP_ROW * rows as i32 + 14 + if s.note.is_some() { STRIP_ROW } else { 0 }) as u32
}

/// The panels' areas: `fig.columns` a row, the rows' heights by `fig.row_weights`,
/// each row under its title (`fig.row_titles`) if it has one.
fn grid<DB: DrawingBackend>(body: &Area<DB>, fig: &Figure) -> DrawResult<Vec<Area<DB>>, DB> {
    let cols = fig.columns.max(1);
    let rows = fig.panels.len().div_ceil(cols).max(1);
    let weights: Vec<u32> = (0..rows)
        .map(|r| fig.row_weights.get(r).copied().unwrap_or(1).max(1))
        .collect();
    let total: u32 = weights.iter().sum();
    let (_, h) = body.dim_in_pixel();
    let mut out = Vec::new();
    let mut rest = body.clone();
    for (r, w) in weights.iter().enumerate() {
        let row = if r + 1 == rows {
            rest.clone()
        } else {
            let (top, bottom) = rest.split_vertically(h * w / total);
            rest = bottom;
            top
        };
        let row = match fig.row_titles.get(r) {
            Some(t) => row.titled(t, (FONT, ROW_TITLE_FONT))?,
            None => row,
        };
        out.extend(row.split_evenly((1, cols)));
    }
    Ok(out)
}

/// The figure's legend strip: entries in columns from [`STRIP_LEFT`] (or one centred
/// row), the note under them in grey.
fn draw_strip<DB: DrawingBackend>(area: &Area<DB>, fig: &Figure) -> DrawResult<(), DB> {
    let s = &fig.strip;
    let font = (FONT, LEGEND_FONT).into_font().color(&BLACK);
    let (w, _) = area.dim_in_pixel();
    let place: Vec<(i32, i32)> = if s.columns == 0 {
        let widths: Vec<i32> = s
            .entries
            .iter()
            .map(|e| text_width(area, &e.text, &font) + SWATCH_W + 8 + 30)
            .collect();
        let mut x = (w as i32 - widths.iter().sum::<i32>() + 30) / 2;
        widths
            .iter()
            .map(|wd| {
                let p = (x, 8);
                x += wd;
                p
            })
            .collect()
    } else {
        let col_w = (w as i32 - STRIP_LEFT - 40) / s.columns as i32;
        (0..s.entries.len())
            .map(|k| {
                (
                    STRIP_LEFT + (k % s.columns) as i32 * col_w,
                    8 + (k / s.columns) as i32 * STRIP_ROW,
                )
            })
            .collect()
    };
    for (e, (x, y)) in s.entries.iter().zip(place) {
        draw_entry(area, e, (x, y + 9), &font)?;
    }
    if let Some(note) = &s.note {
        let rows = strip_height(fig) as i32 / STRIP_ROW - 1;
        let font = (FONT, NOTE_FONT + 1).into_font().color(&NOTE_GREY);
        area.draw(&Text::new(
            note.as_str(),
            (STRIP_LEFT, 8 + rows * STRIP_ROW),
            font,
        ))?;
    }
    Ok(())
}

/// A text's width in `font`, pixels.
fn text_width<DB: DrawingBackend>(area: &Area<DB>, text: &str, font: &TextStyle) -> i32 {
    area.estimate_text_size(text, font)
        .map_or(8 * text.len() as i32, |(w, _)| w as i32)
}

/// One legend entry: its swatch at (x, y) (its left end, vertically centred) and its text.
fn draw_entry<DB: DrawingBackend>(
    area: &Area<DB>,
    e: &Entry,
    (x, y): (i32, i32),
    font: &TextStyle,
) -> DrawResult<(), DB> {
    draw_swatch(area, e.swatch, (x, y))?;
    area.draw(&Text::new(
        e.text.as_str(),
        (x + SWATCH_W + 8, y),
        font.pos(Pos::new(HPos::Left, VPos::Center)),
    ))
}

/// A swatch [`SWATCH_W`] wide from (x, y).
fn draw_swatch<DB: DrawingBackend>(
    area: &Area<DB>,
    s: Swatch,
    (x, y): (i32, i32),
) -> DrawResult<(), DB> {
    let mid = (x + SWATCH_W / 2, y);
    match s {
        Swatch::Line(stroke, mark) => {
            let style = stroke.colour.rgb().stroke_width(stroke.width.max(2));
            let seg = vec![(x, y), (x + SWATCH_W, y)];
            match dash_pattern(stroke.dash, true) {
                None => area.draw(&PathElement::new(seg, style))?,
                Some((on, off)) => area.draw(&DashedPathElement::new(seg, on, off, style))?,
            }
            if let Some(m) = mark {
                draw_mark_px(area, m, stroke.colour, mid)?;
            }
            Ok(())
        }
        Swatch::Mark(m, c) => draw_mark_px(area, m, c, mid),
        Swatch::Blank => Ok(()),
        Swatch::Fill(c, alpha) => area.draw(&Rectangle::new(
            [(x, y - 8), (x + SWATCH_W, y + 8)],
            c.rgb().mix(alpha).filled(),
        )),
    }
}

/// A mark at the pixel `p`.
fn draw_mark_px<DB: DrawingBackend>(
    area: &Area<DB>,
    m: Mark,
    c: Colour,
    p: (i32, i32),
) -> DrawResult<(), DB> {
    let c = c.rgb();
    match m {
        Mark::Dot => area.draw(&Circle::new(p, 4, c.filled())),
        Mark::Ring => {
            area.draw(&Circle::new(p, 4, WHITE.filled()))?;
            area.draw(&Circle::new(p, 4, c.stroke_width(2)))
        }
        Mark::Cross => area.draw(&Cross::new(p, 6, c.stroke_width(3))),
        Mark::Triangle => area.draw(&TriangleMarker::new(p, 8, c.filled())),
    }
}

/// A panel's legend entries: its labelled bands, markers and series, in that order.
fn entries(p: &Panel) -> Vec<Entry> {
    let bands = p.bands.iter().filter_map(|b| {
        let swatch = match b.shape {
            Shape::Whiskers(_) => Swatch::Line(Stroke::solid(b.colour, b.alpha as u32), None),
            _ => Swatch::Fill(b.colour, b.alpha),
        };
        b.label.clone().map(|text| Entry { swatch, text })
    });
    let markers = p.markers.iter().filter_map(|m| {
        let stroke = m.stroke?;
        m.label.clone().map(|text| Entry {
            swatch: Swatch::Line(stroke, None),
            text,
        })
    });
    let series = p.series.iter().filter_map(|s| {
        let swatch = match s.style {
            Style::Line(st, m) => Swatch::Line(st, m),
            Style::Step(st) => Swatch::Line(st, None),
            Style::Points(m, c) => Swatch::Mark(m, c),
        };
        s.label.clone().map(|text| Entry { swatch, text })
    });
    bands.chain(markers).chain(series).collect()
}

/// The height of a panel's x label area, pixels.
fn x_label_area(p: &Panel) -> u32 {
    if p.x.labelled {
        TICK_FONT
            + 12
            + if p.x.label().is_empty() {
                0
            } else {
                AXIS_FONT + 4
            }
    } else {
        10
    }
}

/// The width of a panel's y label area: its widest tick label and its title, pixels.
fn y_label_area<DB: DrawingBackend>(area: &Area<DB>, p: &Panel) -> u32 {
    let Ok((_, yr)) = ranges(p, legend_frac(area, p, entries(p).len())) else {
        return 0;
    };
    let font = (FONT, TICK_FONT).into_font().color(&BLACK);
    let widest = Coord::new(&p.y, yr)
        .major
        .iter()
        .map(|v| text_width(area, &tick_label(&p.y, *v, yr), &font))
        .max()
        .unwrap_or(0)
        .max(0) as u32;
    widest
        + 14
        + if p.y.label().is_empty() {
            0
        } else {
            AXIS_FONT + 16
        }
}

/// One panel: mesh, bands, bars, markers, series, notes and legend; returns its
/// plotting area in pixels.
fn draw_panel<DB: DrawingBackend>(
    area: &Area<DB>,
    p: &Panel,
    y_area: u32,
) -> DrawResult<PixelArea, DB> {
    let (chart_area, legend_area) = match p.legend {
        Legend::Right(w) => {
            let (aw, _) = area.dim_in_pixel();
            let (a, b) = area.split_horizontally(aw.saturating_sub(w));
            (a, Some(b))
        }
        _ => (area.clone(), None),
    };
    let entries = entries(p);
    let frac = legend_frac(&chart_area, p, entries.len());
    let (xr, yr) = ranges(p, frac).map_err(|_| DrawingAreaErrorKind::LayoutError)?;
    let (xc, yc) = (Coord::new(&p.x, xr), Coord::new(&p.y, yr));
    let mut b = ChartBuilder::on(&chart_area);
    if let Some(c) = &p.caption {
        b.caption(c, (FONT, CAPTION_FONT));
    }
    let mut chart = b
        .margin(MARGIN)
        .margin_right(MARGIN_RIGHT)
        .x_label_area_size(x_label_area(p))
        .y_label_area_size(y_area)
        .build_cartesian_2d(xc, yc)?;
    draw_mesh(&mut chart, p, xr, yr)?;
    draw_bands(&mut chart, p, xr, yr)?;
    for b in &p.bars {
        let corners = [(b.x.0, b.y.0), (b.x.1, b.y.1)];
        chart.draw_series(std::iter::once(Rectangle::new(
            corners,
            b.colour.rgb().filled(),
        )))?;
        if let Some(edge) = b.edge {
            chart.draw_series(std::iter::once(Rectangle::new(
                corners,
                edge.rgb().stroke_width(1),
            )))?;
        }
    }
    draw_markers(&mut chart, p, xr, yr)?;
    let (px, py) = chart.plotting_area().get_pixel_range();
    let columns = usize::try_from(px.end - px.start).unwrap_or(1).max(1);
    for s in &p.series {
        draw_series(&mut chart, s, xr, columns)?;
    }
    draw_notes(&chart, p)?;
    let plot = chart.plotting_area().strip_coord_spec();
    match (p.legend, legend_area) {
        (Legend::Inside { .. }, _) if !entries.is_empty() => draw_legend_box(&plot, &entries)?,
        (Legend::Right(_), Some(a)) => draw_legend_column(&a, &entries, &p.legend_notes)?,
        _ => {}
    }
    Ok((px, py))
}

/// The fraction of a panel's height its legend box takes (0 outside [`Legend::Inside`]).
fn legend_frac<DB: DrawingBackend>(area: &Area<DB>, p: &Panel, n: usize) -> f64 {
    let Legend::Inside { rows } = p.legend else {
        return 0.0;
    };
    let (_, h) = area.dim_in_pixel();
    let plot_h = f64::from(
        h.saturating_sub(2 * MARGIN + TICK_FONT + AXIS_FONT + 26)
            .max(1),
    );
    (BOX_ROW * n.max(rows) as f64 + 30.0) / plot_h
}

/// Axes, ticks, titles and grid lines.
fn draw_mesh<DB: DrawingBackend>(
    chart: &mut Chart<'_, DB>,
    p: &Panel,
    xr: (f64, f64),
    yr: (f64, f64),
) -> DrawResult<(), DB> {
    let xf = |v: &f64| tick_label(&p.x, *v, xr);
    let yf = |v: &f64| tick_label(&p.y, *v, yr);
    let (xl, yl) = (
        if p.x.labelled {
            p.x.label()
        } else {
            String::new()
        },
        p.y.label(),
    );
    let mut mesh = chart.configure_mesh();
    mesh.x_label_formatter(&xf)
        .y_label_formatter(&yf)
        .x_labels(64)
        .y_labels(64)
        .label_style((FONT, TICK_FONT))
        .axis_desc_style((FONT, AXIS_FONT))
        .bold_line_style(GRID)
        .light_line_style(GRID_LIGHT)
        .max_light_lines(64);
    if !xl.is_empty() {
        mesh.x_desc(xl);
    }
    if !yl.is_empty() {
        mesh.y_desc(yl);
    }
    if matches!(p.x.ticks, Ticks::Named(_)) {
        mesh.disable_x_mesh();
    }
    if matches!(p.y.ticks, Ticks::Named(_)) {
        mesh.disable_y_mesh();
    }
    mesh.draw()
}

/// Spans of one colour, each at least [`MIN_SPAN_PX`] wide, those that then touch drawn
/// as one (overlapping translucent fills would darken).
fn spans(p: &Panel, min: f64) -> Vec<(Colour, f64, f64, f64)> {
    let mut v: Vec<(Colour, f64, f64, f64)> = p
        .bands
        .iter()
        .filter_map(|b| match b.shape {
            Shape::Span(a, c) => {
                let (a, c) = widen(a, c, min);
                Some((b.colour, b.alpha, a, c))
            }
            _ => None,
        })
        .collect();
    v.sort_by(|x, y| x.2.total_cmp(&y.2));
    let mut out: Vec<(Colour, f64, f64, f64)> = Vec::new();
    for s in v {
        match out.last_mut() {
            Some(l) if l.0 == s.0 && l.1 == s.1 && s.2 <= l.3 => l.3 = l.3.max(s.3),
            _ => out.push(s),
        }
    }
    out
}

/// Spans (see [`spans`]), bands between curves, whiskers.
fn draw_bands<DB: DrawingBackend>(
    chart: &mut Chart<'_, DB>,
    p: &Panel,
    xr: (f64, f64),
    yr: (f64, f64),
) -> DrawResult<(), DB> {
    let per_px = x_per_pixel(chart, xr);
    for (c, alpha, a, b) in spans(p, MIN_SPAN_PX * per_px) {
        let fill = c.rgb().mix(alpha).filled();
        chart.draw_series(std::iter::once(Rectangle::new(
            [(a, yr.0), (b, yr.1)],
            fill,
        )))?;
    }
    for b in &p.bands {
        let fill = b.colour.rgb().mix(b.alpha).filled();
        match &b.shape {
            Shape::Span(..) => {}
            Shape::Between(v) => {
                for run in finite_runs(v) {
                    let mut poly: Vec<(f64, f64)> = run.iter().map(|q| (q.0, q.1)).collect();
                    poly.extend(run.iter().rev().map(|q| (q.0, q.2)));
                    chart.draw_series(std::iter::once(Polygon::new(poly, fill)))?;
                }
            }
            Shape::Whiskers(v) => {
                let style = b.colour.rgb().stroke_width(b.alpha.max(1.0) as u32);
                let cap = 4.0 * per_px;
                chart.draw_series(
                    v.iter()
                        .filter(|q| q.1.is_finite() && q.2.is_finite())
                        .flat_map(|&(x, lo, hi)| {
                            [
                                PathElement::new(vec![(x, lo), (x, hi)], style),
                                PathElement::new(vec![(x - cap, lo), (x + cap, lo)], style),
                                PathElement::new(vec![(x - cap, hi), (x + cap, hi)], style),
                            ]
                        }),
                )?;
            }
        }
    }
    Ok(())
}

/// The x span of one pixel column of the plotting area.
fn x_per_pixel<DB: DrawingBackend>(chart: &Chart<'_, DB>, xr: (f64, f64)) -> f64 {
    let (px, _) = chart.plotting_area().get_pixel_range();
    (xr.1 - xr.0) / f64::from((px.end - px.start).max(1))
}

/// `a..c` widened about its middle to at least `min`.
fn widen(a: f64, c: f64, min: f64) -> (f64, f64) {
    if c - a >= min {
        (a, c)
    } else {
        let m = 0.5 * (a + c);
        (m - 0.5 * min, m + 0.5 * min)
    }
}

/// The runs of consecutive points whose values are all finite.
fn finite_runs(v: &[(f64, f64, f64)]) -> Vec<Vec<(f64, f64, f64)>> {
    let mut out: Vec<Vec<(f64, f64, f64)>> = vec![Vec::new()];
    for q in v {
        if q.0.is_finite() && q.1.is_finite() && q.2.is_finite() {
            if let Some(last) = out.last_mut() {
                last.push(*q);
            }
        } else {
            out.push(Vec::new());
        }
    }
    out.retain(|r| !r.is_empty());
    out
}

/// Marker lines across the panel and their texts at the top (or left) end.
fn draw_markers<DB: DrawingBackend>(
    chart: &mut Chart<'_, DB>,
    p: &Panel,
    xr: (f64, f64),
    yr: (f64, f64),
) -> DrawResult<(), DB> {
    let font = (FONT, NOTE_FONT + 1).into_font().color(&NOTE_GREY);
    let per_px = x_per_pixel(chart, xr);
    for m in &p.markers {
        let (line, text_at) = match m.at {
            At::X(x) => (vec![(x, yr.0), (x, yr.1)], (x + 4.0 * per_px, yr.1)),
            At::Y(y) => (vec![(xr.0, y), (xr.1, y)], (xr.0 + 6.0 * per_px, y)),
        };
        if let Some(s) = m.stroke {
            draw_line(chart, line, s)?;
        }
        if let Some(t) = &m.text {
            chart.draw_series(std::iter::once(Text::new(t.clone(), text_at, font.clone())))?;
        }
    }
    Ok(())
}

/// A polyline in its stroke; a wide solid one segment by segment (a wide polyline's
/// unlimited miter joins shoot far out of the plot at a sharp reversal).
fn draw_line<DB: DrawingBackend>(
    chart: &mut Chart<'_, DB>,
    run: Vec<(f64, f64)>,
    s: Stroke,
) -> DrawResult<(), DB> {
    let style = s.colour.rgb().stroke_width(s.width);
    match dash_pattern(s.dash, false) {
        None if s.width <= 1 => chart.draw_series(LineSeries::new(run, style)).map(|_| ()),
        None => chart
            .draw_series(run.windows(2).filter_map(|w| match w {
                [a, b] => Some(PathElement::new(vec![*a, *b], style)),
                _ => None,
            }))
            .map(|_| ()),
        Some((on, off)) => chart
            .draw_series(DashedLineSeries::new(run, on, off, style))
            .map(|_| ()),
    }
}

/// One series: its line (decimated to the pixel columns, broken at non-finite points)
/// and its marks.
fn draw_series<DB: DrawingBackend>(
    chart: &mut Chart<'_, DB>,
    s: &Series,
    xr: (f64, f64),
    columns: usize,
) -> DrawResult<(), DB> {
    let (stroke, mark, colour) = match s.style {
        Style::Line(st, m) => (Some(st), m, st.colour),
        Style::Step(st) => (Some(st), None, st.colour),
        Style::Points(m, c) => (None, Some(m), c),
    };
    let points = match s.style {
        Style::Step(_) => staircase(&s.points),
        _ => s.points.clone(),
    };
    if let Some(st) = stroke {
        let (xs, ys): (Vec<f64>, Vec<f64>) = points.iter().copied().unzip();
        for run in crate::plot::decimate(&xs, &ys, xr.0..xr.1, columns) {
            draw_line(chart, run, st)?;
        }
    }
    if let Some(m) = mark {
        let area = chart.plotting_area().strip_coord_spec();
        let (bx, by) = area.get_base_pixel();
        for q in s
            .points
            .iter()
            .filter(|q| q.0.is_finite() && q.1.is_finite())
        {
            let (x, y) = chart.plotting_area().map_coordinate(q);
            draw_mark_px(&area, m, colour, (x - bx, y - by))?;
        }
    }
    Ok(())
}

/// A staircase through `points`: each value held to the next point's x.
fn staircase(points: &[(f64, f64)]) -> Vec<(f64, f64)> {
    let mut out = Vec::with_capacity(2 * points.len());
    for w in points.windows(2) {
        if let [a, b] = w {
            out.extend([*a, (b.0, a.1)]);
        }
    }
    out.extend(points.last().copied());
    out
}

/// Notes in data coordinates and the panel's remark at the top centre.
fn draw_notes<DB: DrawingBackend>(chart: &Chart<'_, DB>, p: &Panel) -> DrawResult<(), DB> {
    let area = chart.plotting_area().strip_coord_spec();
    let (bx, by) = area.get_base_pixel();
    for n in &p.notes {
        let (x, y) = chart.plotting_area().map_coordinate(&n.at);
        let h = match n.h {
            HAlign::Left => HPos::Left,
            HAlign::Centre => HPos::Center,
            HAlign::Right => HPos::Right,
        };
        let v = match n.v {
            VAlign::Above => VPos::Bottom,
            VAlign::Middle => VPos::Center,
            VAlign::Below => VPos::Top,
        };
        let size = if n.large { LARGE_NOTE_FONT } else { NOTE_FONT };
        let font = (FONT, size).into_font().color(&n.colour.rgb());
        area.draw(&Text::new(
            n.text.as_str(),
            (x - bx, y - by),
            font.pos(Pos::new(h, v)),
        ))?;
    }
    if let Some(r) = &p.remark {
        let (w, _) = area.dim_in_pixel();
        let f = (FONT, NOTE_FONT + 1)
            .into_font()
            .color(&BLACK)
            .pos(Pos::new(HPos::Center, VPos::Top));
        area.draw(&Text::new(r.as_str(), (w as i32 / 2, 8), f))?;
    }
    Ok(())
}

/// A legend box at the upper right of the plotting area `plot`.
fn draw_legend_box<DB: DrawingBackend>(plot: &Area<DB>, entries: &[Entry]) -> DrawResult<(), DB> {
    let font = (FONT, LEGEND_FONT).into_font().color(&BLACK);
    let (w, _) = plot.dim_in_pixel();
    let text_w = entries
        .iter()
        .map(|e| text_width(plot, &e.text, &font))
        .max()
        .unwrap_or(0);
    let box_w = text_w + SWATCH_W + 8 + 20;
    let box_h = BOX_ROW as i32 * entries.len() as i32 + 14;
    let (x0, y0) = (w as i32 - box_w - 8, 8);
    plot.draw(&Rectangle::new(
        [(x0, y0), (x0 + box_w, y0 + box_h)],
        WHITE.filled(),
    ))?;
    plot.draw(&Rectangle::new(
        [(x0, y0), (x0 + box_w, y0 + box_h)],
        LEGEND_BORDER.stroke_width(1),
    ))?;
    for (k, e) in entries.iter().enumerate() {
        let y = y0 + 7 + BOX_ROW as i32 / 2 + k as i32 * BOX_ROW as i32;
        draw_entry(plot, e, (x0 + 10, y), &font)?;
    }
    Ok(())
}

/// A legend in a column of its own (right of a panel), its notes under it.
fn draw_legend_column<DB: DrawingBackend>(
    area: &Area<DB>,
    entries: &[Entry],
    notes: &[String],
) -> DrawResult<(), DB> {
    let font = (FONT, LEGEND_FONT - 1).into_font().color(&BLACK);
    let row = 19;
    let mut y = 24;
    for e in entries {
        draw_entry(area, e, (6, y), &font)?;
        y += row;
    }
    y += row / 2;
    for n in notes {
        area.draw(&Text::new(
            n.as_str(),
            (6, y),
            font.pos(Pos::new(HPos::Left, VPos::Center)),
        ))?;
        y += row;
    }
    Ok(())
}
