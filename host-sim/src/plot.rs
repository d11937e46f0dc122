//! PNG plots of a run against cam angle (`camsim run --plot DIR`), after the thesis's
//! figures (chapter VI): the follower (load) displacement, velocity and acceleration,
//! each over its theoretical curve with the deviation below; the pressure angle; the
//! motor, coupling and cam angular velocities; the contact force and stress; and the
//! output and drive torques.
//!
//! The cam angle axis is continuous over the revolutions (0 to 360 per revolution, in
//! degrees) with the revolution boundaries marked, and every jump interval (the follower
//! off the cam, Eq. V.20) is shaded. Long series are decimated to the first, lowest,
//! highest and last point of each pixel column, so peaks survive. Text uses DejaVu Sans,
//! embedded in the binary (no system fonts needed).

use std::borrow::Cow;
use std::ops::Range;
use std::sync::OnceLock;

use anyhow::{anyhow, Result};
use camsim_core::{JumpInterval, Sample};
use plotters::coord::ranged1d::{KeyPointHint, NoDefaultFormatting, Ranged, ValueFormatter};
use plotters::coord::types::RangedCoordf64;
use plotters::coord::Shift;
use plotters::element::DashedPathElement;
use plotters::prelude::*;

use crate::output::AtomicDir;
use crate::sim::HostDeviation;

pub mod charts;
pub mod compare;
pub mod montecarlo;
pub mod study;
pub mod sweep;

/// Writes an RGB buffer of `size` pixels as the PNG `file` into the directory output
/// `out` (to the file's temporary: the caller commits `out`). Every plot is saved here.
pub fn save_png(out: &mut AtomicDir, file: &str, rgb: &[u8], size: (u32, u32)) -> Result<()> {
    let path = out.path(file)?;
    image::save_buffer_with_format(
        &path,
        rgb,
        size.0,
        size.1,
        image::ColorType::Rgb8,
        image::ImageFormat::Png,
    )
    .map_err(|e| anyhow!("cannot write plot {}: {e}", out.dir().join(file).display()))
}

/// DejaVu Sans (Bitstream Vera licence, see `host-sim/assets/DejaVuSans-LICENSE.txt`).
static FONT_TTF: &[u8] = include_bytes!("../assets/DejaVuSans.ttf");
/// The family name the embedded font is registered under.
pub(crate) const FONT: &str = "sans-serif";

/// Size of a single-panel plot, pixels.
pub const PLOT_SIZE: (u32, u32) = (1200, 600);
/// Size of a follower-output plot (curves over the theoretical, deviation below), pixels.
pub const FOLLOWER_PLOT_SIZE: (u32, u32) = (1200, 800);
/// Size of the SVAJ plot (four panels), pixels.
pub const SVAJ_PLOT_SIZE: (u32, u32) = (1200, 1400);

const SIMULATED: RGBColor = RGBColor(31, 119, 180);
const THEORY: RGBColor = RGBColor(214, 39, 40);
const SECOND: RGBColor = RGBColor(255, 127, 14);
const THIRD: RGBColor = RGBColor(44, 160, 44);
const JUMP_FILL: RGBColor = RGBColor(255, 150, 150);
const JUMP_ALPHA: f64 = 0.45;
const REV_LINE: RGBColor = RGBColor(90, 90, 90);
const PERIOD_LINE: RGBColor = RGBColor(170, 170, 170);

/// Registers the embedded font with plotters once per process (the study plots use it too).
pub fn ensure_font() -> Result<()> {
    static OK: OnceLock<bool> = OnceLock::new();
    let ok = *OK
        .get_or_init(|| plotters::style::register_font(FONT, FontStyle::Normal, FONT_TTF).is_ok());
    anyhow::ensure!(ok, "the embedded DejaVu Sans font could not be parsed");
    Ok(())
}

/// What the plots need from each sample of a run: one column per quantity, in the
/// units of the plots (angles in degrees).
#[derive(Clone, Debug, Default)]
pub struct PlotData {
    /// Continuous cam angle θ_c, degrees (360 per revolution from the start).
    pub angle_deg: Vec<f64>,
    /// Follower (load) displacement, in.
    pub y: Vec<f64>,
    /// Theoretical displacement, in.
    pub y_theory: Vec<f64>,
    /// Follower (load) velocity, in/s.
    pub v: Vec<f64>,
    /// Theoretical velocity, in/s.
    pub v_theory: Vec<f64>,
    /// Follower (load) acceleration, in/s².
    pub a: Vec<f64>,
    /// Theoretical acceleration, in/s².
    pub a_theory: Vec<f64>,
    /// Pressure angle φ, degrees.
    pub pressure_angle_deg: Vec<f64>,
    /// Motor speed θ̇_m, rad/s.
    pub omega_m: Vec<f64>,
    /// Coupling speed θ̇_cp, rad/s.
    pub omega_cp: Vec<f64>,
    /// Cam speed θ̇_c, rad/s.
    pub omega_c: Vec<f64>,
    /// Contact force F_c (Eq. V.19), lb.
    pub contact_force: Vec<f64>,
    /// Maximum Hertz contact stress, psi.
    pub contact_stress: Vec<f64>,
    /// Output torque on the cam T_o (Eq. IV.1), lb·in.
    pub torque_out: Vec<f64>,
    /// Torque delivered by the drive, lb·in.
    pub torque_drive: Vec<f64>,
    /// Whether the follower touches the cam (false while it jumps, Eq. V.20).
    pub in_contact: Vec<bool>,
    /// Continuous cam angles, degrees, where a new program period (segment) begins.
    pub period_starts_deg: Vec<f64>,
    last_period: Option<(u32, usize)>,
}

impl PlotData {
    /// Records one sample of a run.
    pub fn push(&mut self, s: &Sample<f64>) {
        let p = &s.point;
        let angle = p.theta_c.to_degrees();
        let period = (s.revolution, s.segment);
        if self.last_period.is_some_and(|q| q != period) {
            self.period_starts_deg.push(angle);
        }
        self.last_period = Some(period);
        self.angle_deg.push(angle);
        self.y.push(p.load_displacement());
        self.y_theory.push(s.theory.y);
        self.v.push(p.load_velocity());
        self.v_theory.push(s.theory.v);
        self.a.push(p.load_acceleration());
        self.a_theory.push(s.theory.a);
        self.pressure_angle_deg.push(p.pressure_angle.to_degrees());
        self.omega_m.push(p.omega_m);
        self.omega_cp.push(p.omega_cp);
        self.omega_c.push(p.omega_c);
        self.contact_force.push(p.contact_force);
        self.contact_stress.push(s.contact_stress);
        self.torque_out.push(p.torque_out);
        self.torque_drive.push(p.torque_drive);
        self.in_contact.push(p.in_contact);
    }

    /// The intervals (continuous cam angle, degrees) where the samples show the follower
    /// off the cam: from the first sample off contact to the first one back on (or the
    /// last sample).
    pub fn off_cam_intervals(&self) -> Vec<(f64, f64)> {
        let mut out = Vec::new();
        let mut start = None;
        let mut last = None;
        for (&x, &on) in self.angle_deg.iter().zip(&self.in_contact) {
            match (start, on) {
                (None, false) => start = Some(x),
                (Some(a), true) => {
                    out.push((a, x));
                    start = None;
                }
                _ => {}
            }
            last = Some(x);
        }
        if let (Some(a), Some(b)) = (start, last) {
            out.push((a, b));
        }
        out
    }

    /// Number of recorded samples.
    pub fn len(&self) -> usize {
        self.angle_deg.len()
    }

    /// Whether no sample was recorded.
    pub fn is_empty(&self) -> bool {
        self.angle_deg.is_empty()
    }
}

/// How a curve is stroked.
#[derive(Clone, Copy)]
enum Stroke {
    Solid(u32),
    Dashed(u32),
}

/// One curve of a panel.
struct Curve {
    label: &'static str,
    values: Vec<f64>,
    color: RGBColor,
    stroke: Stroke,
}

impl Curve {
    fn new(label: &'static str, values: &[f64], color: RGBColor, stroke: Stroke) -> Self {
        Self {
            label,
            values: values.to_vec(),
            color,
            stroke,
        }
    }
}

/// One panel: a y axis description and its curves.
struct Panel {
    y_desc: Cow<'static, str>,
    curves: Vec<Curve>,
}

/// One PNG file.
struct Figure {
    file: &'static str,
    title: Cow<'static, str>,
    /// The main panel and, for follower outputs, the deviation panel below it.
    panels: Vec<Panel>,
}

impl Figure {
    fn size(&self) -> (u32, u32) {
        if self.panels.len() > 2 {
            SVAJ_PLOT_SIZE
        } else if self.panels.len() > 1 {
            FOLLOWER_PLOT_SIZE
        } else {
            PLOT_SIZE
        }
    }
}

/// A follower output figure: simulated over theoretical, and their difference below.
fn follower_figure(
    file: &'static str,
    title: &'static str,
    desc: String,
    dev_desc: String,
    sim: &[f64],
    theory: &[f64],
) -> Figure {
    let dev: Vec<f64> = sim.iter().zip(theory).map(|(s, t)| s - t).collect();
    Figure {
        file,
        title: title.into(),
        panels: vec![
            Panel {
                y_desc: desc.into(),
                curves: vec![
                    Curve::new("simulated", sim, SIMULATED, Stroke::Solid(2)),
                    Curve::new(
                        "theoretical (rigid system at ω₀)",
                        theory,
                        THEORY,
                        Stroke::Dashed(2),
                    ),
                ],
            },
            Panel {
                y_desc: dev_desc.into(),
                curves: vec![Curve {
                    label: "simulated − theoretical",
                    values: dev,
                    color: SIMULATED,
                    stroke: Stroke::Solid(1),
                }],
            },
        ],
    }
}

/// `values` times `factor` (a unit conversion of a plotted series).
fn scaled(values: &[f64], factor: f64) -> Vec<f64> {
    values.iter().map(|v| v * factor).collect()
}

/// Every figure `write_all` writes, in order, in the output's unit family.
fn figures(d: &PlotData) -> Vec<Figure> {
    figures_in(d, crate::units::current())
}

/// Every figure `write_all` writes, in order, its axes in `units` (the data are in the
/// inch family; one factor per quantity from [`crate::units`]).
fn figures_in(d: &PlotData, units: crate::units::Units) -> Vec<Figure> {
    use crate::units::{axis_in, ACCELERATION, FORCE};
    use camsim_scene_file::units::{LENGTH, SPEED, STRESS, TORQUE};
    let (fy, uy) = axis_in(LENGTH, units);
    let (fv, uv) = axis_in(SPEED, units);
    let (fa, ua) = axis_in(ACCELERATION, units);
    let (ff, uf) = axis_in(FORCE, units);
    let (fs, us) = axis_in(STRESS, units);
    let (ft, ut) = axis_in(TORQUE, units);
    vec![
        follower_figure(
            "displacement.png",
            "Follower (load) displacement",
            format!("displacement y ({uy})"),
            format!("deviation ({uy})"),
            &scaled(&d.y, fy),
            &scaled(&d.y_theory, fy),
        ),
        follower_figure(
            "velocity.png",
            "Follower (load) velocity",
            format!("velocity ({uv})"),
            format!("deviation ({uv})"),
            &scaled(&d.v, fv),
            &scaled(&d.v_theory, fv),
        ),
        follower_figure(
            "acceleration.png",
            "Follower (load) acceleration",
            format!("acceleration ({ua})"),
            format!("deviation ({ua})"),
            &scaled(&d.a, fa),
            &scaled(&d.a_theory, fa),
        ),
        Figure {
            file: "pressure_angle.png",
            title: "Pressure angle φ".into(),
            panels: vec![Panel {
                y_desc: "pressure angle φ (deg)".into(),
                curves: vec![Curve::new(
                    "φ",
                    &d.pressure_angle_deg,
                    SIMULATED,
                    Stroke::Solid(2),
                )],
            }],
        },
        Figure {
            file: "angular_velocity.png",
            title: "Angular velocities of the drive train".into(),
            panels: vec![Panel {
                y_desc: "angular velocity (rad/s)".into(),
                curves: vec![
                    Curve::new("motor", &d.omega_m, SECOND, Stroke::Solid(4)),
                    Curve::new("coupling", &d.omega_cp, THIRD, Stroke::Solid(2)),
                    Curve::new("cam", &d.omega_c, SIMULATED, Stroke::Solid(1)),
                ],
            }],
        },
        Figure {
            file: "contact_force.png",
            title: "Cam-follower contact force F_c".into(),
            panels: vec![Panel {
                y_desc: format!("contact force Fc ({uf})").into(),
                curves: vec![Curve::new(
                    "F_c",
                    &scaled(&d.contact_force, ff),
                    SIMULATED,
                    Stroke::Solid(2),
                )],
            }],
        },
        Figure {
            file: "contact_stress.png",
            title: "Maximum Hertz contact stress".into(),
            panels: vec![Panel {
                y_desc: format!("contact stress ({us})").into(),
                curves: vec![Curve::new(
                    "stress",
                    &scaled(&d.contact_stress, fs),
                    SIMULATED,
                    Stroke::Solid(2),
                )],
            }],
        },
        Figure {
            file: "torque.png",
            title: "Cam torque".into(),
            panels: vec![Panel {
                y_desc: format!("torque ({ut})").into(),
                curves: vec![
                    Curve::new(
                        "output torque T_o",
                        &scaled(&d.torque_out, ft),
                        SIMULATED,
                        Stroke::Solid(2),
                    ),
                    Curve::new(
                        "drive torque",
                        &scaled(&d.torque_drive, ft),
                        SECOND,
                        Stroke::Solid(2),
                    ),
                ],
            }],
        },
    ]
}

/// The cam angle axis shared by every plot: range, ticks, and the marks on it.
struct AngleAxis {
    range: Range<f64>,
    ticks: Vec<f64>,
    /// Revolution boundaries strictly inside the range, degrees.
    revolutions: Vec<f64>,
    /// Whether the axis is a run's (revolutions counted and labelled) rather than one
    /// revolution of the cam's shape (the SVAJ plot).
    run: bool,
    /// Jump intervals on the continuous axis, degrees.
    jumps: Vec<(f64, f64)>,
    /// Period starts (excluding revolution boundaries), degrees.
    periods: Vec<f64>,
}

impl AngleAxis {
    fn new(d: &PlotData, jumps: &[JumpInterval<f64>]) -> Self {
        let (lo, hi) = finite_bounds(d.angle_deg.iter().copied()).unwrap_or((0.0, 360.0));
        let start = (lo / 360.0).floor() * 360.0;
        let mut end = (hi / 360.0).ceil() * 360.0;
        if end <= start {
            end = start + 360.0;
        }
        let span = end - start;
        let step = [
            5.0, 10.0, 15.0, 30.0, 45.0, 60.0, 90.0, 180.0, 360.0, 720.0, 1440.0, 3600.0,
        ]
        .into_iter()
        .find(|s| span / s <= 16.0)
        .unwrap_or(span / 8.0);
        let ticks: Vec<f64> = (0..)
            .map(|k| start + step * f64::from(k))
            .take_while(|t| *t <= end + 1e-9)
            .collect();
        let revolutions: Vec<f64> = (1..)
            .map(|k| start + 360.0 * f64::from(k))
            .take_while(|r| *r < end - 1e-9)
            .collect();
        // The run's jump list (it may be truncated to its capacity) and the samples'
        // own contact flags, merged.
        let listed = jumps.iter().map(|j| {
            let base = (f64::from(j.revolution) - 1.0) * 360.0;
            (base + j.start_deg, base + j.end_deg)
        });
        let mut all: Vec<(f64, f64)> = listed
            .chain(d.off_cam_intervals())
            .filter_map(|(a, b)| {
                let (a, b) = (a.min(b).max(start), a.max(b).min(end));
                (a.is_finite() && b.is_finite() && b >= a).then_some((a, b))
            })
            .collect();
        all.sort_by(|p, q| p.0.total_cmp(&q.0));
        let jumps = merge_intervals(all, 0.0);
        let periods = d
            .period_starts_deg
            .iter()
            .copied()
            .filter(|p| p.is_finite() && *p > start && *p < end)
            .filter(|p| revolutions.iter().all(|r| (r - p).abs() > 0.5))
            .collect();
        Self {
            range: start..end,
            ticks,
            revolutions,
            run: true,
            jumps,
            periods,
        }
    }
}

/// The cam angle coordinate: linear in degrees with ticks at whole multiples of a
/// degree step (30, 45, 60, 90, ...) rather than plotters' decimal steps.
struct DegreeCoord {
    inner: RangedCoordf64,
    ticks: Vec<f64>,
    minor: Vec<f64>,
}

impl DegreeCoord {
    fn new(axis: &AngleAxis) -> Self {
        let minor = axis
            .ticks
            .windows(2)
            .flat_map(|w| match w {
                [a, b] => vec![*a, 0.5 * (a + b)],
                _ => Vec::new(),
            })
            .chain(axis.ticks.last().copied())
            .collect();
        Self {
            inner: axis.range.clone().into(),
            ticks: axis.ticks.clone(),
            minor,
        }
    }
}

impl Ranged for DegreeCoord {
    type FormatOption = NoDefaultFormatting;
    type ValueType = f64;
    fn map(&self, value: &f64, limit: (i32, i32)) -> i32 {
        self.inner.map(value, limit)
    }
    fn key_points<Hint: KeyPointHint>(&self, hint: Hint) -> Vec<f64> {
        if hint.weight().allow_light_points() {
            self.minor.clone()
        } else {
            self.ticks.clone()
        }
    }
    fn range(&self) -> Range<f64> {
        self.inner.range()
    }
}

impl ValueFormatter<f64> for DegreeCoord {
    fn format(value: &f64) -> String {
        format!("{value:.0}")
    }
}

/// Merges sorted intervals that overlap or are less than `gap` apart.
fn merge_intervals(sorted: Vec<(f64, f64)>, gap: f64) -> Vec<(f64, f64)> {
    let mut out: Vec<(f64, f64)> = Vec::with_capacity(sorted.len());
    for (a, b) in sorted {
        match out.last_mut() {
            Some(last) if a <= last.1 + gap => last.1 = last.1.max(b),
            _ => out.push((a, b)),
        }
    }
    out
}

/// Smallest and largest finite value, if any.
fn finite_bounds(v: impl Iterator<Item = f64>) -> Option<(f64, f64)> {
    v.filter(|x| x.is_finite()).fold(None, |acc, x| match acc {
        None => Some((x, x)),
        Some((lo, hi)) => Some((lo.min(x), hi.max(x))),
    })
}

/// The y range of a panel: the data with a 5 % margin below and, above, room for the
/// legend, which covers the top `legend_frac` of the plotting area.
fn y_range(curves: &[Curve], legend_frac: f64) -> Range<f64> {
    let (mut lo, mut hi) =
        finite_bounds(curves.iter().flat_map(|c| c.values.iter().copied())).unwrap_or((-1.0, 1.0));
    let scale = lo.abs().max(hi.abs());
    if (hi - lo).partial_cmp(&(1e-12 * scale.max(1e-300))) != Some(std::cmp::Ordering::Greater) {
        // Flat data: open a window of ±1 % of its value (or ±1 around zero).
        let half = if scale > 0.0 { 0.01 * scale } else { 1.0 };
        let mid = 0.5 * (lo + hi);
        (lo, hi) = (mid - half, mid + half);
    }
    let span = hi - lo;
    // Data occupy (1 - f) of the height: top margin t span with t = 1.05 f / (1 - f).
    let f = legend_frac.clamp(0.0, 0.6);
    let top = (1.05 * f / (1.0 - f)).max(0.05);
    (lo - 0.05 * span)..(hi + top * span)
}

/// Reduces a polyline to at most four points per pixel column (first, lowest, highest,
/// last, in their original order), so the drawn line and its extremes are unchanged.
/// Non-finite points break the line: each returned run is a connected polyline.
pub fn decimate(
    xs: &[f64],
    ys: &[f64],
    x_range: Range<f64>,
    columns: usize,
) -> Vec<Vec<(f64, f64)>> {
    let n = xs.len().min(ys.len());
    let span = x_range.end - x_range.start;
    let mut runs: Vec<Vec<(f64, f64)>> = Vec::new();
    let mut run: Vec<(f64, f64)> = Vec::new();
    let simple =
        n <= 4 * columns.max(1) || span.partial_cmp(&0.0) != Some(std::cmp::Ordering::Greater);
    let scale = columns.max(1) as f64 / span;
    // Current column: its index and the (index, point) of first, min, max, last.
    type Pt = (usize, (f64, f64));
    let mut bucket: Option<(i64, Pt, Pt, Pt, Pt)> = None;
    let flush = |bucket: &mut Option<(i64, Pt, Pt, Pt, Pt)>, run: &mut Vec<(f64, f64)>| {
        if let Some((_, first, min, max, last)) = bucket.take() {
            let mut pts = [first, min, max, last];
            pts.sort_by_key(|p| p.0);
            let mut prev = None;
            for (i, p) in pts {
                if prev != Some(i) {
                    run.push(p);
                    prev = Some(i);
                }
            }
        }
    };
    for (i, (&x, &y)) in xs.iter().zip(ys).enumerate().take(n) {
        if !(x.is_finite() && y.is_finite()) {
            flush(&mut bucket, &mut run);
            if !run.is_empty() {
                runs.push(std::mem::take(&mut run));
            }
            continue;
        }
        if simple {
            run.push((x, y));
            continue;
        }
        let col = ((x - x_range.start) * scale).floor() as i64;
        let pt = (i, (x, y));
        match bucket.as_mut() {
            Some((c, _, min, max, last)) if *c == col => {
                if y < min.1 .1 {
                    *min = pt;
                }
                if y > max.1 .1 {
                    *max = pt;
                }
                *last = pt;
            }
            _ => {
                flush(&mut bucket, &mut run);
                bucket = Some((col, pt, pt, pt, pt));
            }
        }
    }
    flush(&mut bucket, &mut run);
    if !run.is_empty() {
        runs.push(run);
    }
    runs
}

/// Converts a plotters error to anyhow, naming the file.
fn plot_err<E: std::fmt::Display>(file: &str) -> impl FnOnce(E) -> anyhow::Error + '_ {
    move |e| anyhow!("cannot draw plot {file}: {e}")
}

/// A figure's title: `text` in `size` px, centred across `area`, its top `top` px down.
pub(crate) fn draw_title<DB: DrawingBackend>(
    area: &DrawingArea<DB, Shift>,
    text: &str,
    size: u32,
    top: i32,
) -> Result<(), DrawingAreaErrorKind<DB::ErrorType>> {
    let (w, _) = area.dim_in_pixel();
    area.draw(&Text::new(
        text,
        (w as i32 / 2, top),
        (FONT, size)
            .into_font()
            .color(&BLACK)
            .pos(plotters::style::text_anchor::Pos::new(
                plotters::style::text_anchor::HPos::Center,
                plotters::style::text_anchor::VPos::Top,
            )),
    ))
}

/// Pixel ranges (x, y) of a panel's plotting area.
type PixelArea = (Range<i32>, Range<i32>);

/// Draws one figure on `root`; returns the pixel ranges (x, y) of each panel's plotting area.
fn draw_figure<DB: DrawingBackend>(
    root: &DrawingArea<DB, Shift>,
    fig: &Figure,
    axis: &AngleAxis,
    xs: &[f64],
) -> Result<Vec<PixelArea>, DrawingAreaErrorKind<DB::ErrorType>> {
    root.fill(&WHITE)?;
    let (_, h) = root.dim_in_pixel();
    let mut areas = Vec::new();
    let title_area_h = 44;
    let (title_area, body) = root.split_vertically(title_area_h);
    draw_title(&title_area, fig.title.as_ref(), 26, 12)?;
    let body_h = h.saturating_sub(title_area_h);
    let mut panels_areas = Vec::new();
    if fig.panels.len() > 2 {
        let n = fig.panels.len() as u32;
        let mut rest = body;
        for _ in 1..n {
            let (top, bottom) = rest.split_vertically(body_h / n);
            panels_areas.push(top);
            rest = bottom;
        }
        panels_areas.push(rest);
    } else if fig.panels.len() > 1 {
        let (top, bottom) = body.split_vertically(body_h * 3 / 5);
        panels_areas.push(top);
        panels_areas.push(bottom);
    } else {
        panels_areas.push(body);
    }
    let last = panels_areas.len().saturating_sub(1);
    for (k, (panel, area)) in fig.panels.iter().zip(&panels_areas).enumerate() {
        areas.push(draw_panel(area, panel, axis, xs, k == last)?);
    }
    Ok(areas)
}

/// Draws one panel with its shading, boundaries, curves and legend.
fn draw_panel<DB: DrawingBackend>(
    area: &DrawingArea<DB, Shift>,
    panel: &Panel,
    axis: &AngleAxis,
    xs: &[f64],
    x_labels: bool,
) -> Result<PixelArea, DrawingAreaErrorKind<DB::ErrorType>> {
    let x_label_area = if x_labels { 55 } else { 25 };
    // Legend: about 20 px per entry plus its margins, from the top of the plotting area.
    // Room is kept for the jump entry even without jumps, so a jump never rescales the plot.
    let entries = panel.curves.len() + 1;
    let plot_h = f64::from(
        area.dim_in_pixel()
            .1
            .saturating_sub(12 + x_label_area)
            .max(1),
    );
    let yr = y_range(&panel.curves, (20.0 * entries as f64 + 30.0) / plot_h);
    let (y0, y1) = (yr.start, yr.end);
    let mut chart = ChartBuilder::on(area)
        .margin_left(10)
        .margin_right(25)
        .margin_top(6)
        .margin_bottom(6)
        .x_label_area_size(x_label_area)
        .y_label_area_size(105)
        .build_cartesian_2d(DegreeCoord::new(axis), yr)?;
    let x_fmt = |v: &f64| {
        if x_labels {
            format!("{v:.0}")
        } else {
            String::new()
        }
    };
    let y_fmt = |v: &f64| fmt_tick(*v, y1 - y0);
    let mut mesh = chart.configure_mesh();
    mesh.y_desc(panel.y_desc.as_ref())
        .y_labels(8)
        .x_label_formatter(&x_fmt)
        .y_label_formatter(&y_fmt)
        .label_style((FONT, 17))
        .axis_desc_style((FONT, 19))
        .bold_line_style(RGBColor(215, 215, 215))
        .light_line_style(RGBColor(240, 240, 240))
        .y_max_light_lines(1);
    if x_labels && axis.run {
        mesh.x_desc("cam angle θ (deg, continuous over revolutions)");
    } else if x_labels {
        mesh.x_desc("cam angle θ (deg)");
    }
    mesh.draw()?;

    let (px, py) = chart.plotting_area().get_pixel_range();
    let columns = usize::try_from(px.end - px.start).unwrap_or(1).max(1);
    let deg_per_px = (axis.range.end - axis.range.start) / columns as f64;

    // Jump intervals: at least 3 px wide so a short jump still shows; those that then
    // touch are drawn as one (overlapping translucent fills would darken).
    let min_w = 3.0 * deg_per_px;
    let widened = axis
        .jumps
        .iter()
        .map(|&(a, b)| {
            if b - a < min_w {
                (0.5 * (a + b) - 0.5 * min_w, 0.5 * (a + b) + 0.5 * min_w)
            } else {
                (a, b)
            }
        })
        .collect();
    let mut widened: Vec<(f64, f64)> = widened;
    widened.sort_by(|p, q| p.0.total_cmp(&q.0));
    let mut first = true;
    for (a, b) in merge_intervals(widened, 0.0) {
        let s = chart.draw_series(std::iter::once(Rectangle::new(
            [(a, y0), (b, y1)],
            JUMP_FILL.mix(JUMP_ALPHA).filled(),
        )))?;
        if first {
            s.label("jump (follower off the cam)").legend(|(x, y)| {
                Rectangle::new(
                    [(x, y - 7), (x + 24, y + 7)],
                    JUMP_FILL.mix(JUMP_ALPHA).filled(),
                )
            });
            first = false;
        }
    }
    // Period starts (faint, dotted) and revolution boundaries (dark, dashed, labelled).
    for &p in &axis.periods {
        chart.draw_series(DashedLineSeries::new(
            vec![(p, y0), (p, y1)],
            2,
            5,
            PERIOD_LINE.stroke_width(1),
        ))?;
    }
    let rev_label = (FONT, 15).into_font().color(&REV_LINE);
    chart.draw_series(std::iter::once(Text::new(
        if axis.run { "rev 1" } else { "" },
        (axis.range.start + 6.0 * deg_per_px, y1),
        rev_label.clone(),
    )))?;
    for (k, &r) in axis.revolutions.iter().enumerate() {
        chart.draw_series(DashedLineSeries::new(
            vec![(r, y0), (r, y1)],
            8,
            5,
            REV_LINE.stroke_width(2),
        ))?;
        let label = format!("rev {}", k + 2);
        chart.draw_series(std::iter::once(Text::new(
            label,
            (r + 4.0 * deg_per_px, y1),
            rev_label.clone(),
        )))?;
    }
    // Curves.
    for c in &panel.curves {
        let runs = decimate(xs, &c.values, axis.range.clone(), columns);
        let color = c.color;
        let mut labelled = false;
        for run in runs {
            let ann = match c.stroke {
                Stroke::Solid(w) if w <= 1 => {
                    chart.draw_series(LineSeries::new(run, color.stroke_width(w)))?
                }
                // A wide polyline is drawn with unlimited miter joins, which shoot far
                // out of the plot at the sharp reversals of a vibrating (or decimated)
                // signal: draw wide lines segment by segment instead.
                Stroke::Solid(w) => chart.draw_series(run.windows(2).filter_map(|s| match s {
                    [a, b] => Some(PathElement::new(vec![*a, *b], color.stroke_width(w))),
                    _ => None,
                }))?,
                Stroke::Dashed(w) => {
                    chart.draw_series(DashedLineSeries::new(run, 10, 6, color.stroke_width(w)))?
                }
            };
            if !labelled {
                let ann = ann.label(c.label);
                match c.stroke {
                    Stroke::Solid(w) => ann.legend(move |(x, y)| {
                        PathElement::new(vec![(x, y), (x + 24, y)], color.stroke_width(w.max(2)))
                    }),
                    Stroke::Dashed(w) => ann.legend(move |(x, y)| {
                        DashedPathElement::new(
                            vec![(x, y), (x + 26, y)],
                            7,
                            5,
                            color.stroke_width(w.max(2)),
                        )
                    }),
                };
                labelled = true;
            }
        }
    }
    chart
        .configure_series_labels()
        .position(SeriesLabelPosition::UpperRight)
        .margin(8)
        .label_font((FONT, 16))
        .background_style(WHITE.filled())
        .border_style(RGBColor(160, 160, 160))
        .draw()?;
    Ok((px, py))
}

/// A log axis's key points: `m · 10^k` for each mantissa `m` (1 ≤ m < 10) of `mantissas`,
/// within `[lo, hi]` (a part in 10⁹ either way, for ends computed with `powf`), ascending.
/// Given to plotters (`with_key_points`), they replace its own log key points, which
/// repeat a decade's end (a label drawn twice reads bold).
pub fn log_key_points(lo: f64, hi: f64, mantissas: &[f64]) -> Vec<f64> {
    let mut v = Vec::new();
    if !(lo.is_finite() && hi.is_finite() && lo > 0.0 && hi >= lo) {
        return v;
    }
    let (first, last) = (lo.log10().floor() as i32, hi.log10().ceil() as i32);
    for k in first..=last {
        for m in mantissas {
            let x = m * 10f64.powi(k);
            if x >= lo * (1.0 - 1e-9) && x <= hi * (1.0 + 1e-9) {
                v.push(x);
            }
        }
    }
    v
}

/// Formats a y tick: plain decimals sized to the axis span, scientific for very large or small values.
pub(crate) fn fmt_tick(v: f64, span: f64) -> String {
    if v == 0.0 {
        return "0".into();
    }
    // Small ticks by their own size; large ones by the axis's span too, so one axis
    // never mixes 500000 with 1.00e6.
    let mag = v.abs().max(span.abs() / 10.0);
    if mag < 1e-3 || v.abs().max(span.abs()) >= 1e6 {
        return format!("{v:.2e}");
    }
    // The tick step plotters picks for 8 labels: the smallest 1, 2 or 5 x 10^k >= span / 8.
    let rough = span.abs() / 8.0;
    let decimals = if rough > 0.0 {
        let p = 10f64.powf(rough.log10().floor());
        let step = [1.0, 2.0, 5.0, 10.0]
            .into_iter()
            .map(|m| m * p)
            .find(|s| *s >= rough * (1.0 - 1e-9))
            .unwrap_or(p * 10.0);
        (-(step.log10() + 1e-9).floor()).clamp(0.0, 8.0) as usize
    } else {
        2
    };
    format!("{v:.decimals$}")
}

/// An RGB buffer, its size and its panels' plotting areas.
type RenderedRgb = (Vec<u8>, (u32, u32), Vec<PixelArea>);

/// Draws one figure into an RGB buffer (`size.0 * size.1 * 3` bytes).
fn render(fig: &Figure, axis: &AngleAxis, data: &PlotData) -> Result<RenderedRgb> {
    let size = fig.size();
    let mut buf = vec![0u8; size.0 as usize * size.1 as usize * 3];
    let areas = {
        let root = BitMapBackend::with_buffer(&mut buf, size).into_drawing_area();
        let areas = draw_figure(&root, fig, axis, &data.angle_deg).map_err(plot_err(fig.file))?;
        root.present().map_err(plot_err(fig.file))?;
        areas
    };
    Ok((buf, size, areas))
}

/// Draws the figure number `fig_index` into an RGB buffer; used by the tests.
#[cfg(test)]
fn render_to_buffer(
    fig_index: usize,
    data: &PlotData,
    jumps: &[JumpInterval<f64>],
) -> Result<RenderedRgb> {
    ensure_font()?;
    let axis = AngleAxis::new(data, jumps);
    let figs = figures(data);
    let fig = figs
        .get(fig_index)
        .ok_or_else(|| anyhow!("no such figure"))?;
    render(fig, &axis, data)
}

/// The files `--plot DIR` writes, in the order they are drawn.
pub const FILES: [&str; 8] = [
    "displacement.png",
    "velocity.png",
    "acceleration.png",
    "pressure_angle.png",
    "angular_velocity.png",
    "contact_force.png",
    "contact_stress.png",
    "torque.png",
];

/// The file of the profile deviation plot (actual and measured cams).
pub const PROFILE_FILE: &str = "profile_deviation.png";

/// The files `--plot DIR` writes for an actual or measured cam: [`FILES`] and
/// [`PROFILE_FILE`].
pub const FILES_WITH_PROFILE: [&str; 9] = [
    FILES[0],
    FILES[1],
    FILES[2],
    FILES[3],
    FILES[4],
    FILES[5],
    FILES[6],
    FILES[7],
    PROFILE_FILE,
];

/// Points of the profile plot over one revolution (0.05°).
const PROFILE_SAMPLES: usize = 7200;

/// The profile deviation figure: the lift deviation `e(θ)` over one revolution and,
/// below it, its slope `de/dθ` (whose local extrema FPR counts), with the run's period
/// starts of the first revolution marked.
fn profile_figure(dev: &HostDeviation) -> (Figure, PlotData) {
    let step = 360.0 / PROFILE_SAMPLES as f64;
    let mut axis_data = PlotData::default();
    let (mut e, mut de) = (Vec::new(), Vec::new());
    for k in 0..=PROFILE_SAMPLES {
        let deg = k as f64 * step;
        let p = dev.deviation(deg.to_radians());
        axis_data.angle_deg.push(deg);
        e.push(p.y);
        de.push(p.dy);
    }
    let (fl, ul) = crate::units::axis(camsim_scene_file::units::LENGTH);
    let (fd, ud) = crate::units::axis(crate::units::LENGTH_PER_RAD);
    let fig = Figure {
        file: PROFILE_FILE,
        title: "Profile deviation of the actual cam (lift − program)".into(),
        panels: vec![
            Panel {
                y_desc: format!("lift deviation e ({ul})").into(),
                curves: vec![Curve::new(
                    "e(θ)",
                    &scaled(&e, fl),
                    SIMULATED,
                    Stroke::Solid(1),
                )],
            },
            Panel {
                y_desc: format!("de/dθ ({ud})").into(),
                curves: vec![Curve::new(
                    "de/dθ (FPR counts its extrema)",
                    &scaled(&de, fd),
                    SECOND,
                    Stroke::Solid(1),
                )],
            },
        ],
    };
    (fig, axis_data)
}

/// Draws the profile deviation plot ([`PROFILE_FILE`]) into `out`; `data` gives the
/// period starts of the run's first revolution.
pub fn draw_profile(out: &mut AtomicDir, data: &PlotData, dev: &HostDeviation) -> Result<()> {
    ensure_font()?;
    let (fig, mut axis_data) = profile_figure(dev);
    axis_data.period_starts_deg = data
        .period_starts_deg
        .iter()
        .copied()
        .filter(|p| *p > 0.0 && *p < 360.0)
        .collect();
    let axis = AngleAxis::new(&axis_data, &[]);
    let (buf, size, _) = render(&fig, &axis, &axis_data)?;
    save_png(out, fig.file, &buf, size)
}

/// Points of the SVAJ plot over one revolution (0.05°).
const SVAJ_SAMPLES: usize = 7200;

/// The SVAJ figure of `design`'s program (DYNACAM's S, V, A, J diagram): lift,
/// velocity, acceleration and jerk against cam angle, the derivatives in time at the
/// design's speed ω0 (v = ω dy/dθ, a = ω² d²y/dθ², j = ω³ d³y/dθ³), the segment
/// boundaries marked.
fn svaj_figure(design: &camsim_core::Design<f64>, file: &'static str) -> (Figure, PlotData) {
    let w = design.omega0;
    let rpm = camsim_core::rad_per_s_to_rpm(w);
    let mut axis_data = PlotData::default();
    let (mut s, mut v, mut a, mut j) = (Vec::new(), Vec::new(), Vec::new(), Vec::new());
    for k in 0..=SVAJ_SAMPLES {
        let deg = k as f64 * 360.0 / SVAJ_SAMPLES as f64;
        let f = design.program.follower(deg.to_radians());
        axis_data.angle_deg.push(deg);
        s.push(f.y);
        v.push(f.dy * w);
        a.push(f.d2y * w * w);
        j.push(f.d3y * w * w * w);
    }
    axis_data.period_starts_deg = design
        .program
        .segments()
        .iter()
        .map(|g| g.start_deg)
        .filter(|d| *d > 0.0 && *d < 360.0)
        .collect();
    let panel = |desc: String, label: &'static str, values: &[f64], color| Panel {
        y_desc: desc.into(),
        curves: vec![Curve::new(label, values, color, Stroke::Solid(2))],
    };
    use crate::units::{axis, ACCELERATION, JERK};
    use camsim_scene_file::units::{LENGTH, SPEED};
    let ((fs, us), (fv, uv)) = (axis(LENGTH), axis(SPEED));
    let ((fa, ua), (fj, uj)) = (axis(ACCELERATION), axis(JERK));
    let (s, v, a, j) = (
        scaled(&s, fs),
        scaled(&v, fv),
        scaled(&a, fa),
        scaled(&j, fj),
    );
    let fig = Figure {
        file,
        title: format!("SVAJ of the cam program at {rpm:.0} rpm (grey lines: segment boundaries)")
            .into(),
        panels: vec![
            panel(format!("lift s ({us})"), "lift s", &s, SIMULATED),
            panel(
                format!("velocity v ({uv} at {rpm:.0} rpm)"),
                "velocity v",
                &v,
                SECOND,
            ),
            panel(
                format!("acceleration a ({ua} at {rpm:.0} rpm)"),
                "acceleration a",
                &a,
                THEORY,
            ),
            panel(
                format!("jerk j ({uj} at {rpm:.0} rpm)"),
                "jerk j",
                &j,
                THIRD,
            ),
        ],
    };
    (fig, axis_data)
}

/// Draws the SVAJ plot of `design`'s program as `file` into `out`.
pub fn draw_svaj(
    out: &mut AtomicDir,
    design: &camsim_core::Design<f64>,
    file: &'static str,
) -> Result<()> {
    ensure_font()?;
    let (fig, axis_data) = svaj_figure(design, file);
    let mut axis = AngleAxis::new(&axis_data, &[]);
    axis.run = false;
    let (buf, size, _) = render(&fig, &axis, &axis_data)?;
    save_png(out, fig.file, &buf, size)
}

/// Draws every plot of a run ([`FILES`]) as PNG into the directory output `out` (each
/// file to its temporary: the caller commits `out`).
pub fn draw_all(out: &mut AtomicDir, data: &PlotData, jumps: &[JumpInterval<f64>]) -> Result<()> {
    ensure_font()?;
    let axis = AngleAxis::new(data, jumps);
    for fig in figures(data) {
        let (buf, size, _) = render(&fig, &axis, data)?;
        save_png(out, fig.file, &buf, size)?;
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::output::Plan;
    use std::path::Path;

    /// 1-2-5 key points over four decades, the ends included, each exactly once; none
    /// for a range that is not positive.
    #[test]
    fn log_key_points_are_each_decade_s_mantissas_once() {
        let v = log_key_points(0.05, 200.0, &[1.0, 2.0, 5.0]);
        let want = [
            0.05, 0.1, 0.2, 0.5, 1.0, 2.0, 5.0, 10.0, 20.0, 50.0, 100.0, 200.0,
        ];
        assert_eq!(v.len(), want.len(), "{v:?}");
        for (a, b) in v.iter().zip(want) {
            assert!((a / b - 1.0).abs() < 1e-12, "{a} against {b}");
        }
        // Ends computed with powf land a part in 1e15 off: still in.
        let v = log_key_points(10f64.powf(-8.0), 10f64.powf(-4.0), &[1.0]);
        assert_eq!(v.len(), 5, "{v:?}");
        assert!(log_key_points(0.0, 10.0, &[1.0]).is_empty());
        assert!(log_key_points(10.0, 1.0, &[1.0]).is_empty());
    }

    /// What `camsim run --plot DIR --force` does with the plots.
    fn write_all(dir: &Path, data: &PlotData, jumps: &[JumpInterval<f64>]) -> Result<()> {
        let mut out = Plan::new(true).dir("--plot", dir, &FILES)?.open()?;
        draw_all(&mut out, data, jumps)?;
        out.commit().map(|_| ())
    }

    #[test]
    fn the_declared_files_are_the_figures() {
        let files: Vec<&str> = figures(&PlotData::default())
            .iter()
            .map(|f| f.file)
            .collect();
        assert_eq!(files, FILES);
    }

    #[test]
    fn si_series_are_the_inch_series_times_the_definition_and_titles_name_si() {
        use crate::units::Units;
        let d = synthetic();
        let inch = figures_in(&d, Units::Inch);
        let si = figures_in(&d, Units::Si);
        // 1 in = 25.4 mm; 1 lbf = 0.45359237 kg x 9.80665 m/s^2; 1 psi = 1 lbf/in^2;
        // 1 lb in = 1 lbf x 0.0254 m.
        let lbf = 0.453_592_37 * 9.806_65;
        let expect = [
            ("displacement.png", 25.4, "mm"),
            ("velocity.png", 25.4, "mm/s"),
            ("acceleration.png", 25.4, "mm/s²"),
            ("pressure_angle.png", 1.0, "deg"),
            ("contact_force.png", lbf, "(N)"),
            ("contact_stress.png", lbf / (25.4 * 25.4), "MPa"),
            ("torque.png", lbf * 0.0254, "N·m"),
        ];
        for (file, factor, unit) in expect {
            let find = |figs: &[Figure]| {
                figs.iter()
                    .position(|f| f.file == file)
                    .unwrap_or_else(|| panic!("{file} missing"))
            };
            let (fi, fs) = (&inch[find(&inch)], &si[find(&si)]);
            assert!(
                fs.panels[0].y_desc.contains(unit),
                "{file}: {}",
                fs.panels[0].y_desc
            );
            for (pi, ps) in fi.panels.iter().zip(&fs.panels) {
                for (ci, cs) in pi.curves.iter().zip(&ps.curves) {
                    assert!(!ci.values.is_empty());
                    // Relative to the series' scale (a deviation is a difference of
                    // scaled values: its rounding is of their size).
                    let big = ci.values.iter().fold(0.0f64, |m, v| m.max(v.abs())) * factor;
                    for (a, b) in ci.values.iter().zip(&cs.values) {
                        assert!(
                            (b - a * factor).abs() <= 1e-12 * big,
                            "{file}: {b} vs {a} x {factor}"
                        );
                    }
                }
            }
        }
        assert!(inch[0].panels[0].y_desc.contains("(in)"));
        assert!(inch[7].panels[0].y_desc.contains("lb·in"));
    }

    /// A synthetic two-revolution run: a cycloidal-like rise and return with a small
    /// vibration on top of the theoretical curves, sampled every 0.05 degrees.
    fn synthetic() -> PlotData {
        let mut d = PlotData::default();
        let n = 14_400;
        for i in 0..n {
            let deg = 720.0 * i as f64 / n as f64;
            let th = deg.to_radians();
            let yt = 0.5 * (1.0 - th.cos());
            let vt = 0.5 * th.sin() * 80.0;
            let at = 0.5 * th.cos() * 6400.0;
            let wob = (th * 40.0).sin();
            d.angle_deg.push(deg);
            d.y.push(yt + 0.01 * wob);
            d.y_theory.push(yt);
            d.v.push(vt + 2.0 * wob);
            d.v_theory.push(vt);
            d.a.push(at + 300.0 * wob);
            d.a_theory.push(at);
            d.pressure_angle_deg.push(25.0 * th.sin());
            d.omega_m.push(83.8 + 0.2 * wob);
            d.omega_cp.push(83.8 + 0.3 * wob);
            d.omega_c.push(83.8 + 0.5 * wob);
            d.contact_force.push(100.0 + 50.0 * th.cos());
            d.contact_stress.push(80_000.0 + 20_000.0 * th.cos());
            d.torque_out.push(40.0 * th.sin());
            d.torque_drive.push(40.0 * th.sin() + 5.0 * wob);
            d.in_contact.push(true);
        }
        d.period_starts_deg = vec![90.0, 180.0, 270.0, 360.0, 450.0, 540.0, 630.0];
        d
    }

    fn tmp_dir(name: &str) -> std::path::PathBuf {
        std::env::temp_dir().join(format!("camsim-plot-{}-{name}", std::process::id()))
    }

    /// Width and height from a PNG's signature and IHDR chunk.
    fn png_size(bytes: &[u8]) -> Option<(u32, u32)> {
        const SIG: [u8; 8] = [0x89, b'P', b'N', b'G', 0x0d, 0x0a, 0x1a, 0x0a];
        if bytes.get(..8)? != SIG || bytes.get(12..16)? != b"IHDR" {
            return None;
        }
        let w = u32::from_be_bytes(bytes.get(16..20)?.try_into().ok()?);
        let h = u32::from_be_bytes(bytes.get(20..24)?.try_into().ok()?);
        Some((w, h))
    }

    #[test]
    fn writes_every_plot_as_png_of_the_expected_size() {
        let dir = tmp_dir("all").join("nested");
        let _ = std::fs::remove_dir_all(&dir);
        // DIR may be new, its parent must exist (the output plan checks it).
        std::fs::create_dir_all(tmp_dir("all")).unwrap();
        let d = synthetic();
        let jumps = [JumpInterval {
            revolution: 2,
            start_deg: 100.0,
            end_deg: 130.0,
        }];
        write_all(&dir, &d, &jumps).unwrap();
        let expected = [
            ("displacement.png", FOLLOWER_PLOT_SIZE),
            ("velocity.png", FOLLOWER_PLOT_SIZE),
            ("acceleration.png", FOLLOWER_PLOT_SIZE),
            ("pressure_angle.png", PLOT_SIZE),
            ("angular_velocity.png", PLOT_SIZE),
            ("contact_force.png", PLOT_SIZE),
            ("contact_stress.png", PLOT_SIZE),
            ("torque.png", PLOT_SIZE),
        ];
        for (file, size) in expected {
            let bytes = std::fs::read(dir.join(file)).unwrap();
            assert_eq!(png_size(&bytes), Some(size), "{file}");
            assert!(
                bytes.len() > 10_000,
                "{file} is suspiciously small: {} bytes",
                bytes.len()
            );
        }
        let n = std::fs::read_dir(&dir).unwrap().count();
        assert_eq!(n, expected.len());
        std::fs::remove_dir_all(tmp_dir("all")).unwrap();
    }

    #[test]
    fn errors_name_the_path() {
        // A regular file where the directory should be.
        let base = tmp_dir("err");
        let _ = std::fs::remove_dir_all(&base);
        std::fs::create_dir_all(&base).unwrap();
        let file = base.join("not_a_dir");
        std::fs::write(&file, b"x").unwrap();
        let e = write_all(&file.join("sub"), &synthetic(), &[]).unwrap_err();
        assert!(format!("{e:#}").contains("not_a_dir"), "{e:#}");
        // A directory where a plot file should be.
        let dir = base.join("out");
        std::fs::create_dir_all(dir.join("velocity.png")).unwrap();
        let e = write_all(&dir, &synthetic(), &[]).unwrap_err();
        assert!(format!("{e:#}").contains("velocity.png"), "{e:#}");
        std::fs::remove_dir_all(&base).unwrap();
    }

    /// Pixel (r, g, b) at (x, y) of an RGB buffer.
    fn px(buf: &[u8], w: u32, x: i32, y: i32) -> [u8; 3] {
        let i = (y as usize * w as usize + x as usize) * 3;
        [buf[i], buf[i + 1], buf[i + 2]]
    }

    #[test]
    fn jump_shading_covers_the_interval_and_nothing_else() {
        let d = synthetic();
        // Revolution 2, 100..130 deg -> 460..490 on the 0..720 axis.
        let jumps = [JumpInterval {
            revolution: 2,
            start_deg: 100.0,
            end_deg: 130.0,
        }];
        for fig in [3, 5] {
            let (plain, (w, _), areas) = render_to_buffer(fig, &d, &[]).unwrap();
            let (shaded, _, areas2) = render_to_buffer(fig, &d, &jumps).unwrap();
            assert_eq!(areas, areas2);
            let (xr, yr) = areas[0].clone();
            let col =
                |deg: f64| xr.start + ((deg / 720.0) * f64::from(xr.end - xr.start)).round() as i32;
            let (c0, c1) = (col(460.0), col(490.0));
            // Inside the interval most of the plotting area's pixels changed (all but
            // those under the curves and grid lines drawn on top).
            let mut changed_inside = 0;
            let mut total_inside = 0;
            for x in c0 + 2..c1 - 1 {
                for y in yr.clone() {
                    total_inside += 1;
                    if px(&plain, w, x, y) != px(&shaded, w, x, y) {
                        changed_inside += 1;
                    }
                }
            }
            assert!(
                changed_inside * 10 > total_inside * 8,
                "fig {fig}: {changed_inside}/{total_inside}"
            );
            // A white background pixel inside turns pinkish: red stays high, green/blue drop.
            let y_mid = (yr.start + yr.end) / 2;
            let x_mid = (c0 + c1) / 2;
            let (p, s) = (px(&plain, w, x_mid, y_mid), px(&shaded, w, x_mid, y_mid));
            if p == [255, 255, 255] {
                assert!(s[0] >= 250 && s[1] < 235 && s[2] < 235, "fig {fig}: {s:?}");
            }
            // Left of the interval (away from the legend) nothing changed.
            for x in xr.start..c0 - 3 {
                for y in yr.clone() {
                    assert_eq!(
                        px(&plain, w, x, y),
                        px(&shaded, w, x, y),
                        "fig {fig}: pixel ({x}, {y}) changed"
                    );
                }
            }
        }
    }

    #[test]
    fn a_short_jump_is_still_visible() {
        let d = synthetic();
        let jumps = [JumpInterval {
            revolution: 1,
            start_deg: 200.0,
            end_deg: 200.01,
        }];
        let (plain, (w, _), areas) = render_to_buffer(5, &d, &[]).unwrap();
        let (shaded, _, _) = render_to_buffer(5, &d, &jumps).unwrap();
        let (xr, yr) = areas[0].clone();
        let col = xr.start + ((200.0 / 720.0) * f64::from(xr.end - xr.start)).round() as i32;
        let changed = (yr.start..yr.end)
            .filter(|&y| px(&plain, w, col, y) != px(&shaded, w, col, y))
            .count();
        assert!(changed * 2 > (yr.end - yr.start) as usize, "{changed}");
    }

    #[test]
    fn curves_change_pixels_where_the_data_differ() {
        let d = synthetic();
        let mut bumped = d.clone();
        // Dent the simulated displacement between 500 and 520 degrees only (staying
        // inside the y range, so the axes do not change).
        for (x, y) in bumped.angle_deg.iter().zip(bumped.y.iter_mut()) {
            if (500.0..520.0).contains(x) {
                *y -= 0.3;
            }
        }
        let (a, (w, _), areas) = render_to_buffer(0, &d, &[]).unwrap();
        let (b, _, _) = render_to_buffer(0, &bumped, &[]).unwrap();
        let (xr, _) = areas[0].clone();
        let col =
            |deg: f64| xr.start + ((deg / 720.0) * f64::from(xr.end - xr.start)).round() as i32;
        let (c0, c1) = (col(500.0), col(520.0));
        let mut changed_cols = std::collections::BTreeSet::new();
        for (top_x, top_y) in areas.iter().map(|a| (a.0.clone(), a.1.clone())) {
            for x in top_x {
                for y in top_y.clone() {
                    if px(&a, w, x, y) != px(&b, w, x, y) {
                        changed_cols.insert(x);
                    }
                }
            }
        }
        // The bump is drawn in both panels (curve and deviation) and the deviation
        // panel's y range changes, so pixels change; in the top panel the changes are
        // only at the bump (with the line's width either side).
        assert!(!changed_cols.is_empty());
        let (tx, ty) = areas[0].clone();
        for x in tx {
            for y in ty.clone() {
                if px(&a, w, x, y) != px(&b, w, x, y) {
                    assert!(
                        (c0 - 3..=c1 + 3).contains(&x),
                        "top panel changed at column {x}, bump at {c0}..{c1}"
                    );
                }
            }
        }
        let top_changes = (c0..c1).filter(|&x| changed_cols.contains(&x)).count();
        assert!(top_changes as i32 >= (c1 - c0) / 2, "{top_changes}");
    }

    #[test]
    fn sharp_spikes_stay_inside_the_plotting_area() {
        // A fast, large vibration between 80 and 100 degrees (a few samples per period,
        // like the contact ringing of a real run): drawn as one wide polyline, the miter
        // joins at its reversals shoot far out of the plot.
        let mut d = synthetic();
        for (x, a) in d.angle_deg.iter().zip(d.a.iter_mut()) {
            if (80.0..100.0).contains(x) {
                *a += 1e5
                    * (x * 2.0 * std::f64::consts::PI / 0.17).sin()
                    * (1.0 - (x - 90.0).abs() / 10.0);
            }
        }
        let (buf, (w, h), areas) = render_to_buffer(2, &d, &[]).unwrap();
        let (xr, yr) = areas[0].clone();
        let col =
            |deg: f64| xr.start + ((deg / 720.0) * f64::from(xr.end - xr.start)).round() as i32;
        let (c0, c1) = (col(80.0), col(100.0));
        // Nothing but white above the top panel's plotting area over the vibration.
        for x in c0..c1 {
            for y in 0..yr.start - 1 {
                assert_eq!(
                    px(&buf, w, x, y),
                    [255, 255, 255],
                    "pixel ({x}, {y}) above the plot"
                );
            }
        }
        // Nor any curve colour below the bottom panel's plotting area.
        let bottom = areas.last().unwrap().1.end;
        for x in c0..c1 {
            for y in bottom + 1..h as i32 {
                let p = px(&buf, w, x, y);
                assert!(
                    !(p[2] > 150 && p[0] < 100),
                    "curve pixel ({x}, {y}) below the plot: {p:?}"
                );
            }
        }
        // The vibration itself is drawn up to near the top of the plotting area.
        let top = (yr.start..yr.end).find(|&y| {
            (c0..c1).any(|x| {
                let p = px(&buf, w, x, y);
                p[2] > 150 && p[0] < 100
            })
        });
        assert!(
            top.is_some_and(|t| t < yr.start + (yr.end - yr.start) / 4),
            "{top:?}"
        );
    }

    #[test]
    fn decimation_keeps_extremes_and_bounds_the_point_count() {
        let n = 1_000_000;
        let xs: Vec<f64> = (0..n).map(|i| 720.0 * i as f64 / n as f64).collect();
        let mut ys: Vec<f64> = xs.iter().map(|x| x.to_radians().sin()).collect();
        ys[123_457] = 50.0;
        ys[765_433] = -40.0;
        let runs = decimate(&xs, &ys, 0.0..720.0, 1000);
        assert_eq!(runs.len(), 1);
        let run = &runs[0];
        assert!(run.len() <= 4 * 1001, "{}", run.len());
        let max = run.iter().map(|p| p.1).fold(f64::MIN, f64::max);
        let min = run.iter().map(|p| p.1).fold(f64::MAX, f64::min);
        assert_eq!((max, min), (50.0, -40.0));
        // Order is preserved and the end points are kept.
        assert!(run.windows(2).all(|w| w[0].0 <= w[1].0));
        assert_eq!(run.first().copied(), Some((xs[0], ys[0])));
        assert_eq!(run.last().copied(), Some((xs[n - 1], ys[n - 1])));
    }

    #[test]
    fn decimation_splits_at_non_finite_values() {
        let xs = [0.0, 1.0, 2.0, 3.0, 4.0];
        let ys = [0.0, 1.0, f64::NAN, 3.0, 4.0];
        let runs = decimate(&xs, &ys, 0.0..4.0, 100);
        assert_eq!(
            runs,
            vec![vec![(0.0, 0.0), (1.0, 1.0)], vec![(3.0, 3.0), (4.0, 4.0)]]
        );
    }

    #[test]
    fn angle_axis_spans_whole_revolutions_and_places_jumps() {
        let d = synthetic();
        let jumps = [
            JumpInterval {
                revolution: 2,
                start_deg: 350.0,
                end_deg: 370.0,
            },
            JumpInterval {
                revolution: 1,
                start_deg: 10.0,
                end_deg: 20.0,
            },
        ];
        let a = AngleAxis::new(&d, &jumps);
        assert_eq!(a.range, 0.0..720.0);
        assert_eq!(a.revolutions, vec![360.0]);
        assert_eq!(a.ticks.first(), Some(&0.0));
        assert_eq!(a.ticks.last(), Some(&720.0));
        // Sorted; the carried-over jump is clipped at the end of the axis.
        assert_eq!(a.jumps, vec![(10.0, 20.0), (710.0, 720.0)]);
        // The period start at the revolution boundary is not drawn twice.
        assert!(!a.periods.contains(&360.0));
        assert_eq!(a.periods.len(), 6);
    }

    #[test]
    fn off_cam_intervals_come_from_the_contact_flags_and_merge_with_the_list() {
        let mut d = synthetic();
        // Off the cam from 100 to 150 degrees and from 700 degrees to the end.
        for (x, c) in d.angle_deg.iter().zip(d.in_contact.iter_mut()) {
            *c = !((100.0..150.0).contains(x) || *x >= 700.0);
        }
        let iv = d.off_cam_intervals();
        assert_eq!(iv.len(), 2);
        assert_eq!(iv[0], (100.0, 150.0));
        assert_eq!(iv[1].0, 700.0);
        assert_eq!(iv[1].1, *d.angle_deg.last().unwrap());
        // A listed jump overlapping the first interval merges with it; a separate one stays.
        let jumps = [
            JumpInterval {
                revolution: 1,
                start_deg: 140.0,
                end_deg: 160.0,
            },
            JumpInterval {
                revolution: 2,
                start_deg: 0.0,
                end_deg: 5.0,
            },
        ];
        let a = AngleAxis::new(&d, &jumps);
        assert_eq!(a.jumps.len(), 3);
        assert_eq!(a.jumps[0], (100.0, 160.0));
        assert_eq!(a.jumps[1], (360.0, 365.0));
        assert_eq!(a.jumps[2].0, 700.0);
    }

    #[test]
    fn samples_off_the_cam_are_shaded_without_a_jump_list() {
        let d = synthetic();
        let mut off = d.clone();
        for (x, c) in off.angle_deg.iter().zip(off.in_contact.iter_mut()) {
            *c = !(460.0..490.0).contains(x);
        }
        let (plain, (w, _), areas) = render_to_buffer(6, &d, &[]).unwrap();
        let (shaded, _, _) = render_to_buffer(6, &off, &[]).unwrap();
        let (xr, yr) = areas[0].clone();
        let x_mid = xr.start + ((475.0 / 720.0) * f64::from(xr.end - xr.start)).round() as i32;
        let changed = (yr.start..yr.end)
            .filter(|&y| px(&plain, w, x_mid, y) != px(&shaded, w, x_mid, y))
            .count();
        assert!(changed * 10 > (yr.end - yr.start) as usize * 8, "{changed}");
    }

    #[test]
    fn legend_headroom_keeps_the_data_below_the_legend() {
        let c = [Curve::new("c", &[0.0, 10.0], SIMULATED, Stroke::Solid(1))];
        let r = y_range(&c, 0.25);
        // The data top sits at 75 % of the height from the bottom.
        let frac_top = (10.0 - r.start) / (r.end - r.start);
        assert!((frac_top - 0.75).abs() < 1e-12, "{frac_top}");
        assert_eq!(r.start, -0.5);
        // Flat data still get a window.
        let flat = [Curve::new("c", &[83.8, 83.8], SIMULATED, Stroke::Solid(1))];
        let r = y_range(&flat, 0.0);
        assert!(
            r.start < 83.8 && r.end > 83.8 && r.end - r.start < 3.0,
            "{r:?}"
        );
    }

    #[test]
    fn tick_labels_have_as_many_decimals_as_the_step_needs() {
        assert_eq!(fmt_tick(0.2, 1.2), "0.2"); // step 0.2
        assert_eq!(fmt_tick(1.0, 1.2), "1.0");
        assert_eq!(fmt_tick(0.005, 0.02), "0.005"); // step 0.005
        assert_eq!(fmt_tick(-0.01, 0.02), "-0.010");
        assert_eq!(fmt_tick(90_000.0, 40_000.0), "90000"); // step 5000
        assert_eq!(fmt_tick(83.6, 1.2), "83.6");
        assert_eq!(fmt_tick(0.0, 1.0), "0");
        assert_eq!(fmt_tick(2.5e7, 1e7), "2.50e7");
        // One format on an axis spanning millions (the SVAJ jerk).
        assert_eq!(fmt_tick(500_000.0, 3.5e6), "5.00e5");
    }

    #[test]
    fn empty_data_still_writes_labelled_axes() {
        let dir = tmp_dir("empty");
        let _ = std::fs::remove_dir_all(&dir);
        write_all(&dir, &PlotData::default(), &[]).unwrap();
        let bytes = std::fs::read(dir.join("torque.png")).unwrap();
        assert_eq!(png_size(&bytes), Some(PLOT_SIZE));
        std::fs::remove_dir_all(&dir).unwrap();
    }
}
