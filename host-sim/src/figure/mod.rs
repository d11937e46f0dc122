//! Figures as data: a [`Figure`] is panels of series, bands, bars and markers on axes
//! that carry their quantity, and [`render`] is the one place that draws them (with one
//! style). Every command's plot is described here and drawn by [`draw`].
//!
//! Values are held in the inch family (the reports'), and an axis names its quantity
//! ([`Axis::quantity`]): [`Figure::in_units`] converts every coordinate on that axis and
//! writes the unit into the axis title, once, for the whole figure.

use camsim_scene_file::units::Unit;

use crate::units::Units;

pub mod render;

pub use render::{draw, palette, Colour};

/// Why a figure cannot be drawn.
#[derive(Debug, Clone, PartialEq)]
pub enum FigureError {
    /// A panel holds no finite value to draw on one of its axes (an empty chart says nothing).
    NoFiniteData {
        /// The panel's caption or its y axis title.
        panel: String,
    },
    /// An explicit axis range that is empty, reversed, not finite or (log) not positive.
    BadRange {
        /// The axis's title.
        axis: String,
        /// The range given.
        range: (f64, f64),
    },
}

impl std::fmt::Display for FigureError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            Self::NoFiniteData { panel } => {
                write!(f, "the panel '{panel}' has no finite value to draw")
            }
            Self::BadRange { axis, range } => write!(
                f,
                "the axis '{axis}' has the range {} to {}: it must be finite and increasing (and positive on a log axis)",
                range.0, range.1
            ),
        }
    }
}

impl std::error::Error for FigureError {}

/// How a line is drawn.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Dash {
    /// Continuous.
    Solid,
    /// Long dashes.
    Dashed,
    /// Short dots.
    Dotted,
}

/// A line's colour, width (pixels) and dash.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Stroke {
    /// Its colour.
    pub colour: Colour,
    /// Its width, pixels.
    pub width: u32,
    /// Its dash.
    pub dash: Dash,
}

impl Stroke {
    /// A solid line.
    pub const fn solid(colour: Colour, width: u32) -> Self {
        Self {
            colour,
            width,
            dash: Dash::Solid,
        }
    }
    /// A dashed line.
    pub const fn dashed(colour: Colour, width: u32) -> Self {
        Self {
            colour,
            width,
            dash: Dash::Dashed,
        }
    }
    /// A dotted line.
    pub const fn dotted(colour: Colour, width: u32) -> Self {
        Self {
            colour,
            width,
            dash: Dash::Dotted,
        }
    }
}

/// The shape drawn at a point.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Mark {
    /// A filled dot.
    Dot,
    /// An open circle.
    Ring,
    /// A cross.
    Cross,
    /// A filled triangle (a value off the top of the axis).
    Triangle,
}

/// How a series is drawn.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Style {
    /// A polyline (a non-finite point breaks it), with a mark at each point or none.
    Line(Stroke, Option<Mark>),
    /// A mark at each point, no line.
    Points(Mark, Colour),
    /// A staircase: each value held until the next point.
    Step(Stroke),
}

/// One series of a panel: points (x, y) and how they are drawn.
#[derive(Clone, Debug, PartialEq)]
pub struct Series {
    /// Its legend entry (`None`: not in the legend).
    pub label: Option<String>,
    /// Its points; a non-finite coordinate breaks a line.
    pub points: Vec<(f64, f64)>,
    /// How it is drawn.
    pub style: Style,
}

impl Series {
    /// A line through `points`.
    pub fn line(label: impl Into<Option<String>>, points: Vec<(f64, f64)>, s: Stroke) -> Self {
        Self {
            label: label.into(),
            points,
            style: Style::Line(s, None),
        }
    }
    /// `ys` against `xs`, as a line.
    pub fn of(label: &str, xs: &[f64], ys: &[f64], s: Stroke) -> Self {
        let points = xs.iter().copied().zip(ys.iter().copied()).collect();
        Self::line(label.to_string(), points, s)
    }
}

/// The shape of a shaded range.
#[derive(Clone, Debug, PartialEq)]
pub enum Shape {
    /// The panel's full height between two x values (at least a few pixels wide, so a
    /// short one still shows).
    Span(f64, f64),
    /// Between a lower and an upper curve, each point (x, lo, hi); a non-finite value
    /// breaks the band.
    Between(Vec<(f64, f64, f64)>),
    /// A vertical bar from lo to hi at each x, each point (x, lo, hi) (an interval's whiskers).
    Whiskers(Vec<(f64, f64, f64)>),
}

/// A shaded range.
#[derive(Clone, Debug, PartialEq)]
pub struct Band {
    /// Its legend entry.
    pub label: Option<String>,
    /// Its colour.
    pub colour: Colour,
    /// Its opacity, 0 to 1 (whiskers: their stroke's width in pixels).
    pub alpha: f64,
    /// Its shape.
    pub shape: Shape,
}

/// One filled rectangle in data coordinates (a histogram's bin, a bar of a chart).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Bar {
    /// From and to in x.
    pub x: (f64, f64),
    /// From and to in y.
    pub y: (f64, f64),
    /// Its colour.
    pub colour: Colour,
    /// Its outline (a heat map's cell), or none.
    pub edge: Option<Colour>,
}

/// Where a marker line lies.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum At {
    /// A vertical line at this x.
    X(f64),
    /// A horizontal line at this y.
    Y(f64),
}

/// A marker: a vertical or horizontal line across the panel, its text at the line's top
/// (or left) end, its legend entry.
#[derive(Clone, Debug, PartialEq)]
pub struct Marker {
    /// Where it lies.
    pub at: At,
    /// Its line (`None`: the text alone).
    pub stroke: Option<Stroke>,
    /// Text written beside the line's end.
    pub text: Option<String>,
    /// Its legend entry.
    pub label: Option<String>,
}

/// Where a note's text stands across its anchor.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum HAlign {
    /// Its left edge at the anchor.
    Left,
    /// Centred on the anchor.
    Centre,
    /// Its right edge at the anchor.
    Right,
}

/// Where a note's text stands up and down from its anchor.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum VAlign {
    /// Above the anchor (its bottom at it).
    Above,
    /// Centred on the anchor.
    Middle,
    /// Below the anchor (its top at it).
    Below,
}

/// A text in data coordinates: its anchor point, its text, its alignment and colour.
#[derive(Clone, Debug, PartialEq)]
pub struct Note {
    /// The anchor (x, y).
    pub at: (f64, f64),
    /// The text.
    pub text: String,
    /// Horizontal alignment on the anchor.
    pub h: HAlign,
    /// Vertical alignment on the anchor.
    pub v: VAlign,
    /// Its colour.
    pub colour: Colour,
    /// Whether it is written large (a heat map's cell value, read from afar).
    pub large: bool,
}

impl Note {
    /// Black `text` at `at`, aligned `h` and `v`.
    pub fn new(at: (f64, f64), text: impl Into<String>, h: HAlign, v: VAlign) -> Self {
        Self {
            at,
            text: text.into(),
            h,
            v,
            colour: palette::BLACK,
            large: false,
        }
    }
}

/// The ticks of an axis.
#[derive(Clone, Debug, PartialEq)]
pub enum Ticks {
    /// About this many ticks at 1, 2 or 5 times a power of ten (linear), at decades (log).
    Auto(usize),
    /// At these values, with light grid lines at `minor`.
    At {
        /// Labelled ticks.
        major: Vec<f64>,
        /// Light grid lines.
        minor: Vec<f64>,
    },
    /// Categories: name `k` at the value `k` (0, 1, 2, ...).
    Named(Vec<String>),
}

/// Linear or logarithmic.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Scale {
    /// Linear.
    Linear,
    /// Base-10 logarithmic (non-positive values are not drawn).
    Log,
}

/// An axis: its quantity and unit, its range and ticks.
#[derive(Clone, Debug, PartialEq)]
pub struct Axis {
    /// What is on it, without the unit ("contact force Fc").
    pub title: String,
    /// Its quantity: the values are in its inch member, converted by [`Figure::in_units`].
    pub quantity: Option<Unit>,
    /// The unit written after the title; set by [`Figure::in_units`] from the quantity,
    /// or given for a quantity outside the unit families ("deg", "rpm").
    pub unit: String,
    /// Its range; `None`: the data's, with a margin.
    pub range: Option<(f64, f64)>,
    /// Whether the data's range is widened to include zero.
    pub zero: bool,
    /// Whether values are shown in a power of 1000 ("stress (1000 psi)") when large or small.
    pub thousands: bool,
    /// Linear or log.
    pub scale: Scale,
    /// Its ticks.
    pub ticks: Ticks,
    /// Whether its tick labels and title are drawn (the upper panels of a shared x axis: not).
    pub labelled: bool,
    /// Whether a positive tick label carries its sign ("+20", a change).
    pub signed: bool,
}

impl Axis {
    /// A linear axis of `title` in `quantity` (inch-family values), about 8 ticks.
    pub fn of(title: &str, quantity: Unit) -> Self {
        Self {
            quantity: Some(quantity),
            ..Self::plain(title, "")
        }
    }
    /// A linear axis outside the unit families: `unit` written as given ("" for none).
    pub fn plain(title: &str, unit: &str) -> Self {
        Self {
            title: title.to_string(),
            quantity: None,
            unit: unit.to_string(),
            range: None,
            zero: false,
            thousands: false,
            scale: Scale::Linear,
            ticks: Ticks::Auto(8),
            labelled: true,
            signed: false,
        }
    }
    /// This axis over `lo..hi`.
    pub fn range(mut self, lo: f64, hi: f64) -> Self {
        self.range = Some((lo, hi));
        self
    }
    /// This axis with `ticks`.
    pub fn ticks(mut self, ticks: Ticks) -> Self {
        self.ticks = ticks;
        self
    }
    /// The title with its unit: "contact force (N)", "stress (1000 psi)".
    pub fn label(&self) -> String {
        if self.unit.is_empty() {
            self.title.clone()
        } else {
            format!("{} ({})", self.title, self.unit)
        }
    }
}

/// Where a panel's legend goes.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Legend {
    /// No legend (the figure's strip, or none).
    None,
    /// In a box at the plotting area's upper right, the y range raised so it covers no
    /// data; room kept for at least `rows` entries.
    Inside {
        /// Entries to keep room for.
        rows: usize,
    },
    /// In a column of this many pixels right of the plotting area.
    Right(u32),
}

/// One panel: its axes and what is drawn on them.
#[derive(Clone, Debug, PartialEq)]
pub struct Panel {
    /// A caption above it.
    pub caption: Option<String>,
    /// Its x axis.
    pub x: Axis,
    /// Its y axis.
    pub y: Axis,
    /// Its series, drawn in order over the bands, bars and markers.
    pub series: Vec<Series>,
    /// Its shaded ranges, drawn first.
    pub bands: Vec<Band>,
    /// Its bars.
    pub bars: Vec<Bar>,
    /// Its marker lines.
    pub markers: Vec<Marker>,
    /// Texts in data coordinates.
    pub notes: Vec<Note>,
    /// A line written at the top centre of the plotting area.
    pub remark: Option<String>,
    /// Its legend.
    pub legend: Legend,
    /// Lines written under the legend (a [`Legend::Right`] column).
    pub legend_notes: Vec<String>,
}

impl Panel {
    /// A panel on `x` and `y` with nothing on it yet.
    pub fn new(x: Axis, y: Axis) -> Self {
        Self {
            caption: None,
            x,
            y,
            series: Vec::new(),
            bands: Vec::new(),
            bars: Vec::new(),
            markers: Vec::new(),
            notes: Vec::new(),
            remark: None,
            legend: Legend::None,
            legend_notes: Vec::new(),
        }
    }
    /// Its name in an error: the caption, else the y axis's title.
    pub fn name(&self) -> String {
        self.caption.clone().unwrap_or_else(|| self.y.title.clone())
    }
}

/// What stands for an entry in a legend.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Swatch {
    /// A line sample, with a mark on it or none.
    Line(Stroke, Option<Mark>),
    /// A mark alone.
    Mark(Mark, Colour),
    /// A filled square of a colour and opacity.
    Fill(Colour, f64),
    /// Nothing: the text alone.
    Blank,
}

/// One entry of a legend.
#[derive(Clone, Debug, PartialEq)]
pub struct Entry {
    /// What stands for it.
    pub swatch: Swatch,
    /// Its text.
    pub text: String,
}

/// A figure's legend strip under its title, off the panels.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Strip {
    /// Its entries, in columns.
    pub entries: Vec<Entry>,
    /// Columns (0: one row, centred).
    pub columns: usize,
    /// A grey line under the entries.
    pub note: Option<String>,
}

impl Strip {
    /// A strip of `entries` in one centred row.
    pub fn row(entries: Vec<Entry>) -> Self {
        Self {
            entries,
            columns: 0,
            note: None,
        }
    }
}

/// One PNG: a title, a legend strip, panels in a grid.
#[derive(Clone, Debug, PartialEq)]
pub struct Figure {
    /// Its title.
    pub title: String,
    /// Its size, pixels.
    pub size: (u32, u32),
    /// Its legend strip.
    pub strip: Strip,
    /// Columns of the panel grid (rows follow from the panels).
    pub columns: usize,
    /// The rows' relative heights (empty: equal).
    pub row_weights: Vec<u32>,
    /// A title over each row of panels (empty: none).
    pub row_titles: Vec<String>,
    /// Its panels, row by row.
    pub panels: Vec<Panel>,
}

impl Figure {
    /// A figure of `panels` in one column.
    pub fn new(title: impl Into<String>, size: (u32, u32), panels: Vec<Panel>) -> Self {
        Self {
            title: title.into(),
            size,
            strip: Strip::default(),
            columns: 1,
            row_weights: Vec::new(),
            row_titles: Vec::new(),
            panels,
        }
    }

    /// The figure with every axis in `units`: each coordinate on an axis with a quantity
    /// times that quantity's factor, and its unit written into the axis title; then, on
    /// an axis that asks for it, large or small values in a power of 1000.
    pub fn in_units(mut self, units: Units) -> Self {
        for p in &mut self.panels {
            let fx = convert_axis(&mut p.x, units);
            let fy = convert_axis(&mut p.y, units);
            scale_panel(p, fx, fy);
            let xs: Vec<f64> = p
                .series
                .iter()
                .flat_map(|s| s.points.iter().map(|q| q.0))
                .chain(p.bars.iter().flat_map(|b| [b.x.0, b.x.1]))
                .collect();
            let ys: Vec<f64> = p
                .series
                .iter()
                .flat_map(|s| s.points.iter().map(|q| q.1))
                .chain(p.bars.iter().flat_map(|b| [b.y.0, b.y.1]))
                .collect();
            let fx = thousands(&mut p.x, xs.into_iter());
            let fy = thousands(&mut p.y, ys.into_iter());
            scale_panel(p, fx, fy);
        }
        self
    }
}

/// Sets `a`'s unit from its quantity in `units`; returns the factor on its values.
fn convert_axis(a: &mut Axis, units: Units) -> f64 {
    match a.quantity {
        Some(q) => {
            let (f, unit) = crate::units::axis_in(q, units);
            a.unit = unit;
            f
        }
        None => 1.0,
    }
}

/// On an axis that asks for it, the power of 1000 that shows `values` (and its range)
/// in plain numbers, written into the unit; returns the factor on its values.
fn thousands(a: &mut Axis, values: impl Iterator<Item = f64>) -> f64 {
    if !a.thousands {
        return 1.0;
    }
    let (lo, hi) = a.range.unwrap_or_else(|| {
        values
            .filter(|v| v.is_finite())
            .fold((0.0f64, 0.0f64), |(l, h), v| (l.min(v), h.max(v)))
    });
    let (scale, name) = axis_scale(lo, hi);
    if name.is_empty() {
        return 1.0;
    }
    a.unit = if a.unit.is_empty() {
        format!("× {name}")
    } else {
        format!("{name} {}", a.unit)
    };
    1.0 / scale
}

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

/// Multiplies every x coordinate of `p` by `fx` and every y by `fy`.
fn scale_panel(p: &mut Panel, fx: f64, fy: f64) {
    if fx == 1.0 && fy == 1.0 {
        return;
    }
    let sx = |v: &mut f64| *v *= fx;
    let sy = |v: &mut f64| *v *= fy;
    for a in [(&mut p.x, fx), (&mut p.y, fy)] {
        if let Some(r) = a.0.range.as_mut() {
            *r = (r.0 * a.1, r.1 * a.1);
        }
        if let Ticks::At { major, minor } = &mut a.0.ticks {
            major
                .iter_mut()
                .chain(minor.iter_mut())
                .for_each(|v| *v *= a.1);
        }
    }
    for s in &mut p.series {
        s.points
            .iter_mut()
            .for_each(|q| (q.0, q.1) = (q.0 * fx, q.1 * fy));
    }
    for b in &mut p.bands {
        match &mut b.shape {
            Shape::Span(a, c) => {
                sx(a);
                sx(c);
            }
            Shape::Between(v) | Shape::Whiskers(v) => {
                v.iter_mut()
                    .for_each(|q| (q.0, q.1, q.2) = (q.0 * fx, q.1 * fy, q.2 * fy));
            }
        };
    }
    for b in &mut p.bars {
        b.x = (b.x.0 * fx, b.x.1 * fx);
        b.y = (b.y.0 * fy, b.y.1 * fy);
    }
    for m in &mut p.markers {
        match &mut m.at {
            At::X(x) => sx(x),
            At::Y(y) => sy(y),
        }
    }
    for n in &mut p.notes {
        n.at = (n.at.0 * fx, n.at.1 * fy);
    }
}

#[cfg(test)]
mod tests;
